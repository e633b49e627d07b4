# Pose-graph readers: TORO/MRPT .graph, g2o, rove binary (corpus: fuzz/corpus/graph/).
rove_add_fuzzer(rove_graph_fuzz graph_fuzz.cpp LIBS rove::graph)
