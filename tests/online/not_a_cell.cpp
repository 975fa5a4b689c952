extern "C" int softplc_test_not_a_cell() { return 1; }
