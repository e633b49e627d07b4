# MRPT binary files: rawlogs (RawlogReader over a MemoryInStream) and simple maps.
rove_add_fuzzer(rove_mrpt_rawlog_fuzz ${CMAKE_CURRENT_LIST_DIR}/mrpt_rawlog_fuzz.cpp LIBS rove::io)
