# OctoMap's .bt / .ot files (rove::io).
rove_add_fuzzer(rove_octree_fuzz octree_fuzz.cpp LIBS rove::io)
