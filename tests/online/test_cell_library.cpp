// Cell libraries named in a cell config (`libraries:`, docs/config.md):
// loaded before programs are resolved; a missing file, a dlopen failure, a
// shared object without the ABI symbol and an ABI mismatch are config
// errors at the line of the library's entry, and register nothing.
#include "online_fixture.hpp"
#include "plc/abi.hpp"

namespace plc::test {
namespace {

std::string build_error(CellFolder& folder) {
  try {
    Runtime rt(folder.config());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(CellLibrary, LoadsProgramsFromTheConfigFolder) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V1);
  Runtime rt(folder.config());
  rt.run(io::ClockMode::Virtual, std::chrono::milliseconds(100));
  EXPECT_EQ(value(rt, "Main.build"), "1");
  // 10 scans: the first goes from idle to filling, 9 add 0.125 each.
  EXPECT_EQ(value(rt, "Main.weight"), "1.125");
}

TEST(CellLibrary, MissingFileIsALocatedConfigError) {
  CellFolder folder;
  const std::string e = build_error(folder);
  EXPECT_NE(e.find(folder.config_file() + ":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'libraries': " + folder.library() + ": no such file"), std::string::npos)
      << e;
}

TEST(CellLibrary, UndefinedSymbolIsAConfigError) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_V5);
  const std::string e = build_error(folder);
  EXPECT_NE(e.find("cannot load: " + folder.library()), std::string::npos) << e;
  EXPECT_NE(e.find("undefined symbol: softplc_test_symbol_that_nobody_defines"), std::string::npos)
      << e;
}

TEST(CellLibrary, NotACellLibraryIsAConfigError) {
  CellFolder folder;
  folder.install(PLC_TEST_NOT_A_CELL);
  const std::string e = build_error(folder);
  EXPECT_NE(e.find("not a cell library: it has no symbol softplc_cell_abi_version"),
            std::string::npos)
      << e;
}

TEST(CellLibrary, AbiMismatchIsAConfigErrorAndRegistersNothing) {
  CellFolder folder;
  folder.install(PLC_TEST_FILLER_ABI999);
  const std::string before = [] {
    std::string s;
    for (const auto& n : ProgramRegistry::instance().names()) s += n + " ";
    return s;
  }();
  const std::string e = build_error(folder);
  EXPECT_NE(e.find("built against softplc ABI version 999, this runtime (softplc "),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("has ABI version " + std::to_string(PLC_ABI_VERSION)), std::string::npos) << e;
  std::string after;
  for (const auto& n : ProgramRegistry::instance().names()) after += n + " ";
  EXPECT_EQ(after, before);
}

}  // namespace
}  // namespace plc::test
