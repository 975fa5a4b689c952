#include "cli.hpp"

int main(int argc, char** argv) { return plc::plcrun_main(argc, argv); }
