// The retain file of a cell on disk: two copies, `<file>.a` and `<file>.b`,
// written in turn (odd sequence numbers into .a, even into .b), so that the
// copy being replaced is never the only good one. Each write goes to
// `<file>.tmp`, is fsynced, renamed over its copy, and the folder is
// fsynced, so a crash or power loss at any moment leaves each copy either
// its old or its new complete content (on a disk that honours fsync).
// Loading reads both and takes the valid copy with the highest sequence
// number; a damaged copy is reported and the other used.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "plc/cell_config.hpp"
#include "plc/retain/retain_file.hpp"

namespace plc::retain {

class Storage {
 public:
  explicit Storage(std::string path);

  // Writes a complete file image durably into the copy of `sequence`.
  // "" or why not (the other copy is untouched either way).
  std::string write(std::span<const std::uint8_t> bytes, std::uint64_t sequence);

  struct Loaded {
    std::optional<FileImage> image;     // the newest valid copy, if any
    std::string from;                   // its file
    std::vector<std::string> problems;  // copies that exist but are damaged
  };
  [[nodiscard]] Loaded load() const;

  // Removes both copies (plcrun --reset-retain). "" or why not.
  std::string discard() const;

  // Whether the copies can be written at all: their folder exists, is a
  // folder and is writable (for this process). "" or why not.
  [[nodiscard]] std::string check_folder() const;

  [[nodiscard]] std::string copy_path(std::uint64_t sequence) const;
  [[nodiscard]] const std::string& path() const { return path_; }

  // Tests: stands in for ::write(2) (a full disk, an I/O error).
  using WriteFn = ssize_t (*)(int, const void*, std::size_t);
  void set_write_fn(WriteFn f) { write_fn_ = f; }

  // Files larger than this are not retain files of any cell we build.
  static constexpr std::size_t kMaxFileBytes = std::size_t(256) << 20;

 private:
  std::string path_, dir_;
  WriteFn write_fn_;
};

// Before the cell starts: a retain file whose folder is missing or not
// writable would only show when the first save fails, with the cell
// running and nothing retained. Throws ConfigError at the `file:` value of
// the config's retain: section (which must be present).
void check_file(const CellConfig& cfg);

}  // namespace plc::retain
