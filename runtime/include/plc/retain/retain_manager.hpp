// Retain for one cell: restores RETAIN and PERSISTENT variables at start-up
// as the start mode says (IEC 61131-3 warm / cold start, or a reset), takes
// a snapshot at a scan boundary at most every `save_every`, and saves a last
// one at a controlled stop.
//
// Snapshots: every `save_every` of scan time a snapshot is due. Then each
// task, at the end of its next scan (after its changes are merged, before
// the outputs are published: ScanHooks::before_publish, under the image lock
// in real time), copies its retained variables (and the retained %M, from
// the global image) into the live buffer; so each task's values come from
// one whole scan of it, never a torn one. When every running task has done
// so, the buffer goes to the writer (Writer::offer: one memcpy, or a
// counted skip while the writer is busy). Other scans only compare a time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plc/retain/retain_layout.hpp"
#include "plc/retain/retain_storage.hpp"
#include "plc/retain/retain_writer.hpp"
#include "plc/runtime.hpp"

namespace plc::retain {

enum class StartMode {
  Auto,   // warm when a valid retain file exists, else cold
  Warm,   // RETAIN and PERSISTENT restored, everything else initial
  Cold,   // PERSISTENT restored, RETAIN and everything else initial
  Reset,  // the retain file removed, everything initial
};

struct StartReport {
  StartMode mode = StartMode::Cold;  // what was done (Auto resolved)
  bool loaded = false;               // a valid copy was read
  std::string from;                  // its file
  std::uint64_t sequence = 0;
  std::size_t restored = 0, initial = 0;  // retained entries restored / left initial
  std::vector<std::string> added, removed, type_changed;  // layout differences
  std::vector<std::string> problems;                      // damaged copies, errors
  // The lines plcrun prints.
  [[nodiscard]] std::vector<std::string> lines() const;
};

class Manager : public ScanHooks {
 public:
  Manager(Runtime& rt, const RetainConfig& cfg);
  ~Manager() override;
  Manager(const Manager&) = delete;
  Manager& operator=(const Manager&) = delete;

  // Before the first scan: restores per `mode`, starts the writer and hooks
  // into the scans.
  StartReport start(StartMode mode);
  // After the last scan (Runtime::finish): the last snapshot, written on
  // this thread. "" or the error.
  std::string stop();

  [[nodiscard]] const Layout& layout() const { return layout_; }
  [[nodiscard]] WriterStats stats() const { return writer_.stats(); }
  Writer& writer() { return writer_; }
  Storage& storage() { return storage_; }

  void before_publish(TaskRuntime& t, io::ProcessImage& global) override;

 private:
  Runtime& rt_;
  TIME save_every_;
  Layout layout_;
  Storage storage_;
  Writer writer_;
  std::vector<std::uint8_t> live_;
  TIME next_due_{};
  bool started_ = false;
  // The snapshot being gathered: which tasks copied their part into live_.
  bool gathering_ = false;
  std::vector<bool> captured_;
};

}  // namespace plc::retain
