# rove's own rawlog format: RoveRawlogReader over a MemoryInStream.
rove_add_fuzzer(rove_rove_rawlog_fuzz ${CMAKE_CURRENT_LIST_DIR}/rove_rawlog_fuzz.cpp LIBS rove::io)
