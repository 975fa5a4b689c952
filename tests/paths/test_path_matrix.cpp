// Issue 21 point 1: `plcrun cell.yaml` from inside the cell folder (the
// README's SDK steps) ended with an uncaught filesystem_error (exit 134).
// Every path plcrun takes, in each way it can be written, with the config
// named in each way it can be named, from the current directory that goes
// with it (docs/config.md, "Relative paths"):
// - paths in the config (libraries:, retain: file, hmi: key_file, a GSDML
//   file, a DeviceNet capture) are taken from the config file's folder;
// - paths on the command line (--trace, --record, --replay, --stats-json,
//   --commands) from the current directory.
// Nothing may land in the current directory that belongs beside the config.
#include <gtest/gtest.h>

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "devicenet/child_process.hpp"
#include "path_tree.hpp"

namespace pathtest {
namespace {

const Ref kRefs[] = {Ref::Bare, Ref::Dot, Ref::Parent, Ref::Absolute};
const Form kForms[] = {Form::Bare, Form::Dot, Form::Parent, Form::Absolute};

// ---- paths in the config ---------------------------------------------------

enum class Kind { Library, Retain, KeyFile, Gsdml, Pcap };

struct ConfigCase {
  Kind kind;
  Ref ref;
  Form form;
};

const char* name(Kind k) {
  switch (k) {
    case Kind::Library:
      return "Library";
    case Kind::Retain:
      return "RetainFile";
    case Kind::KeyFile:
      return "HmiKeyFile";
    case Kind::Gsdml:
      return "GsdmlFile";
    case Kind::Pcap:
      return "DeviceNetPcap";
  }
  return "";
}

std::string case_name(const ConfigCase& c) {
  return std::string(name(c.kind)) + "_" + name(c.ref) + "_" + name(c.form);
}
void PrintTo(const ConfigCase& c, std::ostream* os) { *os << case_name(c); }

std::vector<ConfigCase> config_cases() {
  std::vector<ConfigCase> v;
  for (Kind k : {Kind::Library, Kind::Retain, Kind::KeyFile, Kind::Gsdml, Kind::Pcap})
    for (Ref r : kRefs)
      for (Form f : kForms) v.push_back({k, r, f});
  return v;
}

class ConfigPaths : public ::testing::TestWithParam<ConfigCase> {};

TEST_P(ConfigPaths, AreTakenFromTheConfigsFolderWhereverPlcrunStarts) {
  const ConfigCase c = GetParam();
  Tree t(case_name(c));
  const char* file = c.kind == Kind::Library   ? "libpathprobe.so"
                     : c.kind == Kind::Retain  ? "probe.retain"
                     : c.kind == Kind::KeyFile ? "hmi.key"
                     : c.kind == Kind::Gsdml   ? "GSDML-V2.4-softplc-HIWIN-E1-SIM-20261130.xml"
                                               : "bus.pcap";
  const Placed p = t.place(c.form, t.cell(), file);
  std::string library = "build/libpathprobe.so";  // as the cell template writes it
  std::string more;
  switch (c.kind) {
    case Kind::Library:
      fs::copy_file(PLC_TEST_PATH_PROBE, p.real);
      library = p.written;
      break;
    case Kind::Retain:
      more = "retain:\n  file: \"" + p.written + "\"\n";
      break;
    case Kind::KeyFile:
      Tree::write(p.real, std::string(64, 'a') + "\n");
      more = "hmi:\n  url: \"memq://\"\n  key_file: \"" + p.written + "\"\n";
      break;
    case Kind::Gsdml:
      fs::copy_file(plctest::source_path("iec-io/profinet/gsdml/") + file, p.real);
      more =
          "plugins:\n  - {name: pn, type: profinet, params: {interface: \"mem:paths\"}}\n"
          "devices:\n  - name: axis\n    plugin: pn\n    model: gsdml\n"
          "    input: \"%IB0\"\n    output: \"%QB0\"\n"
          "    params: {station_name: axis, ip: 192.168.0.10, gsdml: \"" +
          p.written + "\", gsdml_modules: \"1=ID_Mod_Tel3\"}\n";
      break;
    case Kind::Pcap:
      more = "plugins:\n  - name: dn\n    type: devicenet\n    params: {bus: \"udp:127.0.0.1:" +
             std::to_string(dntest::free_udp_port()) + "\", hub: true, log: false, pcap: \"" +
             p.written + "\"}\n";
      break;
  }
  t.write_config(probe_cell(library, more));

  if (c.kind == Kind::Gsdml) {
    // The description is read while the cell is built; the controller
    // would wait for a device that is not there.
    const auto r = t.plcrun(c.ref, "--list-vars");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Probe.scans DINT retain\n"), std::string::npos) << r.output;
  } else if (c.kind == Kind::KeyFile) {
    // A cell with an hmi: section runs as a debugger session (no
    // --print-vars there): the summary shows it ran.
    const auto r = t.plcrun(c.ref, "--cycles 10 -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("cycles 10 "), std::string::npos) << r.output;
  } else {
    const auto r = t.plcrun(c.ref, "--cycles 10 -q --print-vars Probe.scans");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Probe.scans = 10\n"), std::string::npos) << r.output;
  }
  if (c.kind == Kind::Retain) {
    fs::path a = p.real, b = p.real;
    a += ".a";
    b += ".b";
    EXPECT_TRUE(fs::exists(a) || fs::exists(b)) << p.real;
    // A warm start from wherever it starts finds the same file.
    const auto again = t.plcrun(c.ref, "--cycles 10 -q --print-vars Probe.scans");
    ASSERT_EQ(again.exit_code, 0) << again.output;
    EXPECT_NE(again.output.find("Probe.scans = 20\n"), std::string::npos) << again.output;
  }
  if (c.kind == Kind::Pcap) {
    ASSERT_TRUE(fs::exists(p.real)) << p.real;
    EXPECT_GE(fs::file_size(p.real), 24U) << "the pcap global header";
  }
  EXPECT_EQ(t.stray_in_work(), "");
}

INSTANTIATE_TEST_SUITE_P(EachKindRefAndForm, ConfigPaths, ::testing::ValuesIn(config_cases()),
                         [](const auto& info) { return case_name(info.param); });

// ---- paths on the command line ---------------------------------------------

enum class Arg { Trace, Record, Replay, StatsJson, Commands };

struct ArgCase {
  Arg arg;
  Ref ref;
  Form form;
};

const char* name(Arg a) {
  switch (a) {
    case Arg::Trace:
      return "Trace";
    case Arg::Record:
      return "Record";
    case Arg::Replay:
      return "Replay";
    case Arg::StatsJson:
      return "StatsJson";
    case Arg::Commands:
      return "Commands";
  }
  return "";
}

std::string case_name(const ArgCase& c) {
  return std::string(name(c.arg)) + "_" + name(c.ref) + "_" + name(c.form);
}
void PrintTo(const ArgCase& c, std::ostream* os) { *os << case_name(c); }

std::vector<ArgCase> arg_cases() {
  std::vector<ArgCase> v;
  for (Arg a : {Arg::Trace, Arg::Record, Arg::Replay, Arg::StatsJson, Arg::Commands})
    for (Ref r : {Ref::Bare, Ref::Parent})  // from the cell folder, and from another
      for (Form f : kForms) v.push_back({a, r, f});
  return v;
}

class CommandLinePaths : public ::testing::TestWithParam<ArgCase> {};

TEST_P(CommandLinePaths, AreTakenFromTheCurrentDirectory) {
  const ArgCase c = GetParam();
  Tree t(case_name(c));
  t.write_config(probe_cell("build/libpathprobe.so"));
  const Placed p = t.place(c.form, t.cwd(c.ref), "out.file");
  const std::string w = quoted(p.written);
  switch (c.arg) {
    case Arg::Trace: {
      const auto r = t.plcrun(c.ref, "--cycles 10 -q --trace " + w + " --trace-vars Probe.scans");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_EQ(plctest::read_file(p.real.string()).rfind("time_ns,cycle,", 0), 0U) << p.real;
      break;
    }
    case Arg::Record:
    case Arg::Replay: {
      const auto r = t.plcrun(c.ref, "--cycles 10 -q --record " + w);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_NE(r.output.find("recorded 10 scans into " + p.written), std::string::npos)
          << r.output;
      ASSERT_TRUE(fs::exists(p.real)) << p.real;
      if (c.arg == Arg::Record) break;
      const auto replay = t.plcrun(c.ref, "-q --replay " + w);
      ASSERT_EQ(replay.exit_code, 0) << replay.output;
      EXPECT_NE(replay.output.find("replay: 10 scans, 0 with different outputs"), std::string::npos)
          << replay.output;
      break;
    }
    case Arg::StatsJson: {
      const auto r = t.plcrun(c.ref, "--cycles 10 -q --stats-json " + w);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_NE(plctest::read_file(p.real.string()).find("\"scans\": 10,"), std::string::npos)
          << p.real;
      break;
    }
    case Arg::Commands: {
      Tree::write(p.real, "step 10\nprint Probe.scans\n");
      const auto r = t.plcrun(c.ref, "--commands " + w);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_NE(r.output.find("Probe.scans = 10"), std::string::npos) << r.output;
      break;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EachArgRefAndForm, CommandLinePaths, ::testing::ValuesIn(arg_cases()),
                         [](const auto& info) { return case_name(info.param); });

// ---- the README's SDK steps, every mode ------------------------------------

// `plcrun cell.yaml` from inside the cell folder with the template's
// `libraries: [build/libmycell.so]`: the report, also with
// --list-vars, --debug and --commands (each ended with exit 134).
TEST(ConfigPaths, ABareConfigNameWithLibrariesWorksInEveryMode) {
  Tree t("every_mode");
  t.write_config(probe_cell("build/libpathprobe.so"));
  Tree::write(t.cell() / "cmds.txt", "step 3\nprint Probe.scans\n");
  struct Row {
    const char* args;
    const char* expect;
  };
  const Row rows[] = {
      {"--for 10s -q --print-vars Probe.scans", "Probe.scans = 1000\n"},
      {"--list-vars", "Probe.scans DINT retain\n"},
      {"--debug", "plcrun debugger"},
      {"--commands cmds.txt", "Probe.scans = 3"},
  };
  for (const Row& row : rows) {
    const auto r = t.plcrun(Ref::Bare, row.args);
    EXPECT_EQ(r.exit_code, 0) << row.args << "\n" << r.output;
    EXPECT_NE(r.output.find(row.expect), std::string::npos) << row.args << "\n" << r.output;
  }
}

// ---- dnslave ---------------------------------------------------------------

struct SlaveCase {
  Ref ref;
  Form form;
};

std::string case_name(const SlaveCase& c) { return std::string(name(c.ref)) + "_" + name(c.form); }
void PrintTo(const SlaveCase& c, std::ostream* os) { *os << case_name(c); }

std::vector<SlaveCase> slave_cases() {
  std::vector<SlaveCase> v;
  for (Ref r : kRefs)
    for (Form f : kForms) v.push_back({r, f});
  return v;
}

class DnslavePcap : public ::testing::TestWithParam<SlaveCase> {};

// dnslave's `pcap:` is a path in its config: taken from the config's folder.
TEST_P(DnslavePcap, IsTakenFromTheConfigsFolder) {
  const SlaveCase c = GetParam();
  Tree t("dnslave_" + case_name(c));
  const Placed p = t.place(c.form, t.cell(), "slaves.pcap");
  t.write_config("bus: \"udp:127.0.0.1:" + std::to_string(dntest::free_udp_port()) +
                 "\"\nhub: true\npcap: \"" + p.written +
                 "\"\nslaves:\n  - {name: scale, model: pr5510, params: {bus: devicenet}, mac: 5, "
                 "profile: pr1721_34}\n");
  const auto r =
      Tree::run_in(t.cwd(c.ref), "dnslave", quoted(t.config_arg(c.ref)) + " --for 100ms");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(p.real)) << p.real << "\n" << r.output;
  EXPECT_GE(fs::file_size(p.real), 24U) << "the pcap global header";
  EXPECT_EQ(t.stray_in_work(), "");
}

INSTANTIATE_TEST_SUITE_P(EachRefAndForm, DnslavePcap, ::testing::ValuesIn(slave_cases()),
                         [](const auto& info) { return case_name(info.param); });

}  // namespace
}  // namespace pathtest
