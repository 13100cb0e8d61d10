// A shared library with an ordinary exported function and nothing else.
extern "C" __attribute__((visibility("default"))) int gdsmc_test_answer() { return 42; }
