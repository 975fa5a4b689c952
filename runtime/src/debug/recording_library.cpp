// The library builds a recording ran (recording.hpp, "Online change during
// a recording"): where the recorder keeps its copy of each, and which file
// a replay loads for one.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "plc/cell_library.hpp"
#include "plc/debug/recording.hpp"
#include "plc/online_change.hpp"

namespace plc::debug {

namespace fs = std::filesystem;

namespace {

std::string hex8(std::uint32_t v) {
  char s[9];
  std::snprintf(s, sizeof s, "%08x", v);
  return s;
}

std::string describe(const std::optional<FileCrc>& c) {
  return c ? "build CRC-32 " + hex8(c->crc32) + " (" + std::to_string(c->size) + " bytes)"
           : "missing";
}

}  // namespace

std::string library_copy_path(const std::string& recording, const std::string& library,
                              std::uint32_t crc32) {
  return (fs::path(recording + ".libs") /
          (fs::path(library).filename().string() + "." + hex8(crc32)))
      .string();
}

std::string find_library_build(const std::string& recording, const std::string& library,
                               std::uint32_t crc32, std::uint64_t size) {
  const FileCrc want{crc32, size};
  const auto at_path = file_crc32(library);
  if (at_path == want) return library;
  const std::string copy = library_copy_path(recording, library, crc32);
  const auto kept = file_crc32(copy);
  if (kept == want) return copy;
  throw RecordingError("the recording ran " + describe(want) + " of the library " + library +
                       "; the file there is " + describe(at_path) + " and the recording's copy " +
                       copy + " is " + describe(kept) +
                       ": put that build back at either place to replay it");
}

void Recorder::keep_copy(const CellLibrary& lib) {
  // Best effort: a replay without the copy names what is missing.
  const FileCrc want{lib.crc32(), lib.size()};
  const std::string copy = library_copy_path(file_, lib.path(), lib.crc32());
  if (file_crc32(copy) == want || file_crc32(lib.path()) != want) return;
  std::error_code ec;
  fs::create_directories(fs::path(copy).parent_path(), ec);
  fs::copy_file(lib.path(), copy, fs::copy_options::overwrite_existing, ec);
}

void Recorder::put_change(recfmt::Buf& b, std::uint16_t task, std::uint32_t number,
                          const CellLibrary& lib, const std::string& report) {
  const std::size_t path = std::min<std::size_t>(lib.path().size(), recfmt::kMaxPathBytes);
  const std::size_t text = std::min<std::size_t>(report.size(), recfmt::kMaxReportBytes);
  b.begin(recfmt::kChange);
  b.le(task);
  b.le(number);
  b.le(static_cast<std::uint16_t>(path));
  b.bytes(lib.path().data(), path);
  b.le(lib.crc32());
  b.le(lib.size());
  b.le(static_cast<std::uint32_t>(text));
  b.bytes(report.data(), text);
  b.end();
}

std::string Recorder::note_change(const OnlineChange& change, const std::string& report) {
  bool started = false;
  rt_.with_image_locked([&] { started = active_; });
  if (!started)
    return "the recording has not started yet (it starts at a latch): step a scan first, so "
           "that its snapshot is of the build it begins with";
  for (const TaskRec& ts : tasks_)
    if (ts.change_due.load(std::memory_order_acquire))
      return "the recording has not yet noted the previous change";
  const CellLibrary& lib = *change.next_library();
  keep_copy(lib);
  ++changes_;
  for (std::size_t t : change.tasks()) {
    TaskRec& ts = tasks_[t];
    ts.change.reserve_fixed(64 + lib.path().size() + report.size());
    put_change(ts.change, static_cast<std::uint16_t>(t), changes_, lib, report);
    ts.change_due.store(true, std::memory_order_release);
  }
  return "";
}

}  // namespace plc::debug
