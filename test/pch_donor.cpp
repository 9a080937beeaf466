// The translation unit that compiles the test executables' shared precompiled header
// (RADAR_NDT_TEST_PCH, test/CMakeLists.txt); it has nothing of its own.
