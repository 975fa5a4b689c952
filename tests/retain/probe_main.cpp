// plcrun with the retain test programs linked in (the crash test runs it).
#include "cli.hpp"

int main(int argc, char** argv) { return plc::plcrun_main(argc, argv); }
