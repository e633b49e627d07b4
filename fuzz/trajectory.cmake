# Trajectory and relations readers: TUM, KITTI, Freiburg relations
# (corpus: fuzz/corpus/trajectory/).
rove_add_fuzzer(rove_trajectory_fuzz trajectory_fuzz.cpp LIBS rove::slam)
