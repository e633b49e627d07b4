# Point-cloud file readers and LZF (rove::io).
rove_add_fuzzer(rove_pcd_fuzz pcd_fuzz.cpp LIBS rove::io)
rove_add_fuzzer(rove_ply_fuzz ply_fuzz.cpp LIBS rove::io)
rove_add_fuzzer(rove_lzf_fuzz lzf_fuzz.cpp LIBS rove::io)
