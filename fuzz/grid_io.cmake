# Occupancy-grid files (rove::io): PNG/PGM images, ROS map.yaml, .rovegrid.
rove_add_fuzzer(rove_grid_io_fuzz grid_io_fuzz.cpp LIBS rove::io)
