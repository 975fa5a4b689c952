// The GSD parser (PROFIBUS GSD specification: keywords, modules,
// continuation lines, comments, ExtUserPrmData / PrmText) on the seed's
// GWT_5610.gsd (sartorius-pr1721.md §1.2) and on small files of our own;
// every error names the file and the line.
#include <gtest/gtest.h>

#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/gsd/gsd.hpp"
#include "plc/profibus/slave/from_gsd.hpp"
#include "plc_test_paths.hpp"
#include "runtime/test_helpers.hpp"

using namespace plc::profibus;
using gsd::GsdError;

namespace {
std::string error_of(const std::string& text) {
  try {
    gsd::parse_gsd(text, "t.gsd");
  } catch (const GsdError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// The seed's listing verbatim from #Profibus_DP to the last EndModule
// (seed 004, lines 285-380). The PDF conversion wrapped two German comments
// onto lines of their own ("Baudraten", line 26; "Wartungsgerätes", line 42)
// and left markdown fences (lines 48, 50): the parser stops at the first
// with its line, as it must for a line that is no keyword.
TEST(Gsd, SeedListingVerbatimStopsAtTheWrappedCommentLine_Spec1_2) {
  try {
    gsd::load_gsd(plctest::source_path("tests/profibus/data/GWT_5610_seed.gsd"));
    FAIL() << "the verbatim listing parsed";
  } catch (const GsdError& e) {
    EXPECT_EQ(e.line, 26u) << e.what();
    EXPECT_NE(std::string(e.what()).find("'Baudraten' is not 'Keyword = Value'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("GWT_5610_seed.gsd:26: "), std::string::npos);
  }
}

// The shipped file is the listing with the two comment words joined back
// to their lines and the fences removed (nothing else differs; checked
// line by line).
TEST(Gsd, ShippedFileIsTheSeedWithOnlyTheConversionArtefactsRepaired) {
  const std::string seed =
      plctest::read_file(plctest::source_path("tests/profibus/data/GWT_5610_seed.gsd"));
  const std::string ours =
      plctest::read_file(plctest::source_path("iec-io/profibus/gsd/GWT_5610.gsd"));
  std::string expected;
  std::size_t pos = 0;
  while (pos < seed.size()) {
    const std::size_t nl = seed.find('\n', pos);
    const std::string line = seed.substr(pos, nl - pos);
    pos = nl == std::string::npos ? seed.size() : nl + 1;
    if (line == "```") continue;
    if (line == "Baudraten" || line.rfind("Wartungsger", 0) == 0) {
      expected.back() = ' ';
      expected += line + "\n";
      continue;
    }
    expected += line + "\n";
  }
  EXPECT_EQ(ours, expected);
}

// §1.2: every keyword the spec lists, read from the shipped file.
TEST(Gsd, Pr1721KeywordsAndTenModules_Spec1_2) {
  const gsd::Gsd g = gsd::load_gsd(plctest::source_path("iec-io/profibus/gsd/GWT_5610.gsd"));
  EXPECT_EQ(g.ident(), 0x5610);
  EXPECT_EQ(g.text("Vendor_Name"), "GLOBAL Weighing Technologies");
  EXPECT_EQ(g.text("Model_Name"), "PR1721/xx Profibus Interface");
  EXPECT_EQ(g.text("Implementation_Type"), "SPC3");
  EXPECT_EQ(g.number("Protocol_Ident", -1), 0);
  EXPECT_EQ(g.number("Station_Type", -1), 0);
  EXPECT_EQ(g.max_diag_len(), 6u);
  EXPECT_TRUE(g.freeze_supported());
  EXPECT_TRUE(g.sync_supported());
  EXPECT_TRUE(g.modular());
  EXPECT_EQ(g.max_modules(), 4u);
  EXPECT_EQ(g.number("Max_Input_Len", 0), 64);
  EXPECT_EQ(g.number("Max_Data_Len", 0), 128);
  EXPECT_EQ(g.min_slave_interval(), 50u);  // x 100 us = 5 ms
  EXPECT_EQ(g.number("User_Prm_Data_Len", -1), 0);
  EXPECT_EQ(g.number("Set_Slave_Add_supp", -1), 0);
  EXPECT_TRUE(g.baud_supported("12M"));
  EXPECT_FALSE(g.baud_supported("45.45"));  // not listed
  EXPECT_EQ(g.max_tsdr("9.6"), 60u);
  EXPECT_EQ(g.max_tsdr("500"), 100u);
  EXPECT_EQ(g.max_tsdr("1.5M"), 150u);
  EXPECT_EQ(g.max_tsdr("12M"), 800u);
  EXPECT_FALSE(g.max_tsdr("45.45"));
  // The module table of §1.2: name, Cfg byte, bytes each way.
  struct Row {
    const char* name;
    std::uint8_t cfg;
    std::size_t bytes;
  };
  const Row rows[] = {{"8 Byte I/O Konsistent", 0xB7, 8},   {"16 Byte I/O Konsistent", 0xBF, 16},
                      {"8 Byte I/O Seperate", 0x37, 8},     {"16 Byte I/O Seperate", 0x3F, 16},
                      {"4 Word I/O Konsistent", 0xF3, 8},   {"8 Word I/O Konsistent", 0xF7, 16},
                      {"16 Word I/O Konsistent", 0xFF, 32}, {"4 Word I/O Seperate", 0x73, 8},
                      {"8 Word I/O Seperate", 0x77, 16},    {"16 Word I/O Seperate", 0x7F, 32}};
  ASSERT_EQ(g.modules.size(), 10u);
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_EQ(g.modules[i].name, rows[i].name);
    ASSERT_EQ(g.modules[i].cfg.size(), 1u);
    EXPECT_EQ(g.modules[i].cfg[0], rows[i].cfg) << rows[i].name;
    EXPECT_EQ(g.modules[i].input_bytes, rows[i].bytes) << rows[i].name;
    EXPECT_EQ(g.modules[i].output_bytes, rows[i].bytes) << rows[i].name;
  }
  EXPECT_EQ(g.module("16 word i/o konsistent")->cfg[0], 0xFF);
  EXPECT_EQ(g.module("32 Byte I/O"), nullptr);
  EXPECT_TRUE(g.user_prm_data({g.module("8 Byte I/O Konsistent")}).empty());
  // What dpslavesim's slave is checked against, from these keywords.
  const auto c = slave::slave_config_from_gsd(g, 5, 8, 8);
  EXPECT_EQ(c.ident, 0x5610);
  EXPECT_EQ(c.max_modules, 4u);
  EXPECT_EQ(c.modules.size(), 10u);
  EXPECT_EQ(c.max_diag_len, 6u) << "Max_Diag_Data_Len: the 6-byte diagnosis of §1.2";
  EXPECT_EQ(c.user_prm_len, 0u);
}

// Continuation lines, comments (also after a string with ';' in it),
// indexed keywords, ExtUserPrmData with Bit/BitArea/Unsigned16 defaults and
// a PrmText, module-level parameters and a module reference.
TEST(Gsd, ContinuationCommentsAndUserParameters) {
  const std::string text =
      "; a comment\n"
      "#Profibus_DP\n"
      "Vendor_Name = \"A; B\"   ; the ';' in the string is no comment\n"
      "Ident_Number = 0x00C1\n"
      "User_Prm_Data_Len = 3\n"
      "Ext_User_Prm_Data_Const(0) = 0x80, \\\n"
      "                             0x00\n"
      "Ext_User_Prm_Data_Ref(0) = 1\n"
      "Ext_User_Prm_Data_Ref(1) = 2\n"
      "PrmText = 7\n"
      "Text(0) = \"off\"\n"
      "Text(1) = \"on\"\n"
      "EndPrmText\n"
      "ExtUserPrmData = 1 \"Diagnosis\"\n"
      "Bit(2) 1 0-1\n"
      "Prm_Text_Ref = 7\n"
      "EndExtUserPrmData\n"
      "ExtUserPrmData = 2 \"Filter\"\n"
      "Unsigned16 0x1234 0-0xFFFF\n"
      "EndExtUserPrmData\n"
      "ExtUserPrmData = 3 \"Range\"\n"
      "BitArea(4-6) 2 1,2,4\n"
      "EndExtUserPrmData\n"
      "Module = \"2 AI\" 0x40,0x41, \\\n"
      "  0x00\n"
      "  17\n"
      "Ext_Module_Prm_Data_Len = 1\n"
      "Ext_User_Prm_Data_Ref(0) = 3\n"
      "EndModule\n";
  const gsd::Gsd g = gsd::parse_gsd(text, "t.gsd");
  EXPECT_EQ(g.text("vendor_name"), "A; B");
  EXPECT_EQ(g.ident(), 0xC1);
  ASSERT_EQ(g.modules.size(), 1u);
  const gsd::Module& m = g.modules[0];
  EXPECT_EQ(m.cfg, (std::vector<std::uint8_t>{0x40, 0x41, 0x00}));
  EXPECT_EQ(m.reference, 17u);
  // 0x40: special format, an input length byte follows (0x41 = 2 words),
  // then an empty slot (0x00).
  EXPECT_EQ(m.input_bytes, 4u);
  EXPECT_EQ(m.output_bytes, 0u);
  EXPECT_EQ(g.prm_texts.at(7).texts.at(1), "on");
  EXPECT_EQ(g.ext_user_prm.at(3).allowed, (std::vector<std::int64_t>{1, 2, 4}));
  // Const 80 00, then bit 2 of byte 0 set, Unsigned16 0x1234 at offset 1
  // (MSB first), then the module's byte with bits 4-6 = 2.
  EXPECT_EQ(g.user_prm_data({&m}), (std::vector<std::uint8_t>{0x84, 0x12, 0x34, 0x20}));
}

TEST(Gsd, ErrorsNameTheLine) {
  EXPECT_EQ(error_of("Vendor_Name = \"x\"\n"),
            "t.gsd:1: 'Vendor_Name = \"x\"' before #Profibus_DP");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nEndModule\n"),
            "t.gsd:3: EndModule without Module");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nModule = \"m\" 0x1FF\nEndModule\n"),
            "t.gsd:3: Cfg byte: '0x1FF' is not a byte (0..255)");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nModule = \"m\"\nEndModule\n"),
            "t.gsd:3: module 'm' without Cfg bytes");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nModule = \"m\" 0x40\nEndModule\n"),
            "t.gsd:3: module 'm': malformed Cfg bytes 40");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nModule = \"m\" 0x10\n"),
            "t.gsd:3: the file ends inside a block");
  EXPECT_EQ(error_of("#Profibus_DP\nVendor_Name = \"x\n"),
            "t.gsd:2: a string without its closing '\"'");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1 \\"),
            "t.gsd:2: a continuation '\\' at the end of the file");
  EXPECT_EQ(error_of("#Profibus_DP\nVendor_Name = \"x\"\n"), "t.gsd:1: Ident_Number missing");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 0x10000\n"),
            "t.gsd:2: Ident_Number outside 0..0xFFFF");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nExtUserPrmData = 1 \"p\"\nFloat 1 0-2\n"
                     "EndExtUserPrmData\n"),
            "t.gsd:4: unknown parameter type 'Float'");
  EXPECT_EQ(error_of("#Profibus_DP\nIdent_Number = 1\nExtUserPrmData = 1 \"p\"\nUnsigned8 9 0-2\n"
                     "EndExtUserPrmData\n"),
            "t.gsd:4: default 9 outside its range");
  EXPECT_EQ(error_of("\n#Profibus_DP\nIdent_Number = 1\nExt_User_Prm_Data_Ref(0) = 5\n"),
            "t.gsd:1: Ext_User_Prm_Data_Ref to undefined parameter 5");
  // A numeric keyword that is not a number fails when it is read, at its line.
  const gsd::Gsd g = gsd::parse_gsd("#Profibus_DP\nIdent_Number = 1\nMax_Module = many\n", "t.gsd");
  try {
    (void)g.max_modules();
    FAIL();
  } catch (const GsdError& e) {
    EXPECT_STREQ(e.what(), "t.gsd:3: Max_Module: 'many' is not a number");
  }
  try {
    gsd::load_gsd("/nonexistent/x.gsd");
    FAIL();
  } catch (const GsdError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/x.gsd:0: cannot read the file");
  }
}

// DP identifier bytes (EN 50170 DP §8.3.8): general and special formats.
TEST(DpCfg, IdentifierSizes) {
  const std::uint8_t pr[] = {0xB7, 0xFF};  // 8 B + 16 words each way
  auto s = dp::cfg_sizes(pr);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->input_bytes, 40u);
  EXPECT_EQ(s->output_bytes, 40u);
  EXPECT_EQ(s->identifiers, 2u);
  const std::uint8_t special[] = {0xC2, 0x83, 0x01, 0xAA, 0xBB, 0x00, 0x10};
  // C2: out and in length bytes, 2 manufacturer bytes: out 4 B consistent,
  // in 2 B; then an empty slot (00) and 1 input byte (10).
  s = dp::cfg_sizes(special);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->output_bytes, 4u);
  EXPECT_EQ(s->input_bytes, 3u);
  const std::uint8_t cut[] = {0xC0, 0x01};
  EXPECT_FALSE(dp::cfg_sizes(cut));
}
