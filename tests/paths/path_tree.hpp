// A folder tree of its own for one path test, and plcrun started in a
// chosen current directory of it (by the shell that runs it: the test
// process never changes its own directory):
//
//   ROOT/cell/cell.yaml              the config; ROOT/cell is "the config's folder"
//   ROOT/cell/build/libpathprobe.so  the cell library, where the template puts it
//   ROOT/cell/sub/, ROOT/work/sub/   targets of "./sub/x"
//   ROOT/work/                       the current directory when the config is
//                                    named as ../cell/cell.yaml or absolute
//   ROOT/files/                      the target of "../files/x" from cell/ or work/
//   ROOT/abs/                        the target of absolute paths
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "runtime/test_helpers.hpp"

namespace pathtest {

namespace fs = std::filesystem;

// How the command line names the config (and so where plcrun starts).
enum class Ref { Bare, Dot, Parent, Absolute };
// How a path is written: x, ./sub/x, ../files/x, /ROOT/abs/x.
enum class Form { Bare, Dot, Parent, Absolute };

inline const char* name(Ref r) {
  switch (r) {
    case Ref::Bare:
      return "BareConfig";
    case Ref::Dot:
      return "DotConfig";
    case Ref::Parent:
      return "ParentConfig";
    case Ref::Absolute:
      return "AbsoluteConfig";
  }
  return "";
}

inline const char* name(Form f) {
  switch (f) {
    case Form::Bare:
      return "BarePath";
    case Form::Dot:
      return "DotPath";
    case Form::Parent:
      return "ParentPath";
    case Form::Absolute:
      return "AbsolutePath";
  }
  return "";
}

inline std::string quoted(const std::string& s) { return "'" + s + "'"; }

// A file as a path form writes it, and where it really is.
struct Placed {
  std::string written;
  fs::path real;
};

class Tree {
 public:
  explicit Tree(const std::string& test) : root_(plctest::temp_path("paths_" + test)) {
    std::error_code ec;
    fs::remove_all(root_, ec);
    for (const char* d : {"cell/build", "cell/sub", "work/sub", "files", "abs"})
      fs::create_directories(root_ / d);
    fs::copy_file(PLC_TEST_PATH_PROBE, cell() / "build" / "libpathprobe.so");
  }
  ~Tree() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  Tree(const Tree&) = delete;
  Tree& operator=(const Tree&) = delete;

  [[nodiscard]] fs::path root() const { return root_; }
  [[nodiscard]] fs::path cell() const { return root_ / "cell"; }
  [[nodiscard]] fs::path work() const { return root_ / "work"; }
  [[nodiscard]] fs::path cwd(Ref r) const {
    return r == Ref::Bare || r == Ref::Dot ? cell() : work();
  }
  [[nodiscard]] std::string config_arg(Ref r) const {
    switch (r) {
      case Ref::Bare:
        return "cell.yaml";
      case Ref::Dot:
        return "./cell.yaml";
      case Ref::Parent:
        return "../cell/cell.yaml";
      case Ref::Absolute:
        return (cell() / "cell.yaml").string();
    }
    return "";
  }

  // The file `name` written in `form`, relative to `from` (the config's
  // folder for a config's path, the current directory for an argument).
  [[nodiscard]] Placed place(Form form, const fs::path& from, const std::string& name) const {
    switch (form) {
      case Form::Bare:
        return {name, from / name};
      case Form::Dot:
        return {"./sub/" + name, from / "sub" / name};
      case Form::Parent:
        return {"../files/" + name, root_ / "files" / name};
      case Form::Absolute:
        return {(root_ / "abs" / name).string(), root_ / "abs" / name};
    }
    return {};
  }

  void write_config(const std::string& text) const { write(cell() / "cell.yaml", text); }
  static void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

  // `program` (plcrun, dnslave) with `args`, started in `cwd`, stdin empty.
  static plctest::RunResult run_in(const fs::path& cwd, const std::string& program,
                                   const std::string& args) {
    return plctest::run_command("cd " + quoted(cwd.string()) + " && exec " +
                                quoted(plctest::bin_dir() + "/" + program) + " " + args +
                                " </dev/null");
  }
  // plcrun CONFIG args, CONFIG named as `ref` says, from its directory.
  [[nodiscard]] plctest::RunResult plcrun(Ref ref, const std::string& args) const {
    return run_in(cwd(ref), "plcrun", quoted(config_arg(ref)) + " " + args);
  }

  // What a run left in ROOT/work besides its empty sub/ (a file written
  // from the current directory instead of the config's folder).
  [[nodiscard]] std::string stray_in_work() const {
    std::string s;
    for (const auto& e : fs::recursive_directory_iterator(work()))
      if (e.path() != work() / "sub") s += e.path().string() + " ";
    return s;
  }

 private:
  fs::path root_;
};

// The cell of the path tests: PathProbe from the library at `library`.
inline std::string probe_cell(const std::string& library, const std::string& more = "") {
  return "cell: paths\n"
         "libraries: [\"" +
         library +
         "\"]\n"
         "tasks:\n"
         "  - {name: main, period: 10ms, programs: [Probe]}\n"
         "programs:\n"
         "  - {name: Probe, type: PathProbe}\n" +
         more;
}

}  // namespace pathtest
