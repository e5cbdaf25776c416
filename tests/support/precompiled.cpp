// The source of allanlot_test_pch, the target that precompiles the headers every test program
// shares (tests/CMakeLists.txt); the header itself is CMake's, written from that list.
