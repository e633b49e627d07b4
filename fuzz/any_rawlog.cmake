# Any robot log through format detection (AnyRawlogReader), from a scratch file.
rove_add_fuzzer(rove_any_rawlog_fuzz ${CMAKE_CURRENT_LIST_DIR}/any_rawlog_fuzz.cpp LIBS rove::io)
