// The one source of the precompiled-header anchor targets
// (cmake/precompiled_headers.cmake). A main, as two of them are executables.
int main() { return 0; }
