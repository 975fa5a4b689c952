// Golden traces and recordings (issue 23): the example cells that run in
// virtual time in one process run for a fixed span with a trace of every
// program variable and every device byte (*.vars) and a recording (--record);
// both are compared with digests made on the code before the virtual-time
// optimisations (*.golden). A change that makes a scan cheaper must leave
// every value of every scan, and every byte of the recording, as it was.
//
// A trace of 500 variables over 60 s is 150 MB of CSV (2.7 MB with xz), too
// big to commit, so a digest holds FNV-1a 64 hashes: of the header, of each
// block of 1,000 rows, of each column over the whole run, and of each
// 64 KiB of the recording. A difference is located by the first block (a
// span of scans) and the columns (the variables) that differ; the new files
// are kept for a look.
//
// When a merge legitimately changes a cell's behaviour, re-record the
// digests (scripts/golden-record) and say why in the commit.
// PLC_GOLDEN_WRITE=1 makes this test write the digests instead of comparing.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/test_helpers.hpp"

namespace {

constexpr std::uint64_t kBlockRows = 1000;
constexpr std::size_t kChunkBytes = 64 << 10;

std::uint64_t fnv1a(std::uint64_t h, const char* p, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(p[i])) * 1099511628211ULL;
  return h;
}
constexpr std::uint64_t kFnvBasis = 1469598103934665603ULL;

struct Digest {
  std::uint64_t rows = 0;
  std::uint64_t header = 0;
  std::vector<std::uint64_t> blocks;  // rows [k * kBlockRows, (k + 1) * kBlockRows)
  std::vector<std::pair<std::string, std::uint64_t>> columns;
  std::uint64_t recording_bytes = 0;
  std::vector<std::uint64_t> chunks;  // bytes [k * kChunkBytes, (k + 1) * kChunkBytes)
};

std::string hex(std::uint64_t v) {
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
  return b;
}

// Every row's text goes into its block's hash; each cell of the row into
// its column's hash (the row's time and scan number included).
bool digest_trace(const std::string& csv, Digest& d, std::string& err) {
  std::ifstream in(csv);
  std::string line;
  if (!std::getline(in, line)) {
    err = "empty trace " + csv;
    return false;
  }
  d.header = fnv1a(kFnvBasis, line.data(), line.size());
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) d.columns.emplace_back(c, kFnvBasis);
  while (std::getline(in, line)) {
    if (d.rows % kBlockRows == 0) d.blocks.push_back(kFnvBasis);
    d.blocks.back() = fnv1a(d.blocks.back(), line.data(), line.size() + 1);  // with the '\0'
    std::size_t col = 0, start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i) {
      if (i < line.size() && line[i] != ',') continue;
      if (col >= d.columns.size()) {
        err = "row " + std::to_string(d.rows) + " has more cells than the header";
        return false;
      }
      auto& h = d.columns[col++].second;
      h = fnv1a(h, line.data() + start, i - start + 1);  // with the separator
      start = i + 1;
    }
    if (col != d.columns.size()) {
      err = "row " + std::to_string(d.rows) + " has fewer cells than the header";
      return false;
    }
    ++d.rows;
  }
  return true;
}

void digest_recording(const std::string& file, Digest& d) {
  const std::string bytes = plctest::read_file(file);
  d.recording_bytes = bytes.size();
  for (std::size_t at = 0; at < bytes.size(); at += kChunkBytes)
    d.chunks.push_back(
        fnv1a(kFnvBasis, bytes.data() + at, std::min(kChunkBytes, bytes.size() - at)));
}

std::string to_text(const Digest& d, const std::string& what) {
  std::string s = "# Golden digest of " + what + " (tests/golden/test_golden.cpp).\n";
  s += "rows " + std::to_string(d.rows) + "\nheader " + hex(d.header) + "\n";
  for (std::size_t k = 0; k < d.blocks.size(); ++k)
    s += "block " + std::to_string(k) + " " + hex(d.blocks[k]) + "\n";
  for (const auto& [name, h] : d.columns) s += "column " + name + " " + hex(h) + "\n";
  s += "recording_bytes " + std::to_string(d.recording_bytes) + "\n";
  for (std::size_t k = 0; k < d.chunks.size(); ++k)
    s += "chunk " + std::to_string(k) + " " + hex(d.chunks[k]) + "\n";
  return s;
}

bool from_text(const std::string& text, Digest& d) {
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ls(line);
    std::string key, a, b;
    ls >> key >> a;
    if (key == "rows") {
      d.rows = std::stoull(a);
    } else if (key == "header") {
      d.header = std::stoull(a, nullptr, 16);
    } else if (key == "block" && ls >> b) {
      d.blocks.push_back(std::stoull(b, nullptr, 16));
    } else if (key == "column" && ls >> b) {
      d.columns.emplace_back(a, std::stoull(b, nullptr, 16));
    } else if (key == "recording_bytes") {
      d.recording_bytes = std::stoull(a);
    } else if (key == "chunk" && ls >> b) {
      d.chunks.push_back(std::stoull(b, nullptr, 16));
    } else {
      return false;
    }
  }
  return true;
}

// Where `got` differs from `want`: the first block of rows, the columns
// (at most 20 named), the first chunk of the recording. Empty: identical.
std::string differences(const Digest& want, const Digest& got) {
  std::string s;
  if (got.header != want.header) s += "the header (the traced columns) differs; ";
  if (got.rows != want.rows)
    s += "rows: " + std::to_string(got.rows) + ", golden " + std::to_string(want.rows) + "; ";
  for (std::size_t k = 0; k < std::min(want.blocks.size(), got.blocks.size()); ++k) {
    if (want.blocks[k] != got.blocks[k]) {
      s += "first difference in rows " + std::to_string(k * kBlockRows) + ".." +
           std::to_string((k + 1) * kBlockRows - 1) + "; ";
      break;
    }
  }
  if (got.columns.size() == want.columns.size()) {
    int named = 0, differ = 0;
    std::string cols;
    for (std::size_t c = 0; c < want.columns.size(); ++c) {
      if (want.columns[c].second == got.columns[c].second) continue;
      ++differ;
      if (named++ < 20) cols += " " + want.columns[c].first;
    }
    if (differ) s += std::to_string(differ) + " column(s) differ:" + cols + "; ";
  }
  if (got.recording_bytes != want.recording_bytes)
    s += "recording: " + std::to_string(got.recording_bytes) + " bytes, golden " +
         std::to_string(want.recording_bytes) + "; ";
  for (std::size_t k = 0; k < std::min(want.chunks.size(), got.chunks.size()); ++k) {
    if (want.chunks[k] != got.chunks[k]) {
      s += "recording differs first in bytes " + std::to_string(k * kChunkBytes) + ".." +
           std::to_string((k + 1) * kChunkBytes - 1) + "; ";
      break;
    }
  }
  return s;
}

std::vector<std::string> read_vars(const std::string& file) {
  std::vector<std::string> vars;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') vars.push_back(line);
  return vars;
}

// Runs `config` for `span` of virtual time with the trace and the
// recording, and checks (or writes) the cell's digest. Without `record` the
// run has only the trace, and only the trace's part of the digest is
// compared: a recording hook makes the scans copy and merge the whole image
// (ScanHooks::whole_image), so this is the run that checks the bytes a
// plain run copies (only those its programs and devices are bound to).
void check_cell(const std::string& name, const std::string& config, const std::string& span,
                const std::string& vars_file, bool record = true) {
  const std::string dir = plctest::source_path("tests/golden/");
  const std::vector<std::string> vars = read_vars(dir + vars_file);
  ASSERT_FALSE(vars.empty()) << dir + vars_file;
  std::string list;
  for (const std::string& v : vars) list += (list.empty() ? "" : ",") + v;
  const std::string csv = plctest::temp_path("golden_" + name + ".csv");
  const std::string rec = plctest::temp_path("golden_" + name + ".rec");
  const auto r =
      plctest::run_command(plctest::plcrun_path() + " " + plctest::source_path(config) +
                           " --virtual --for " + span + " -q --trace " + csv + " --trace-vars '" +
                           list + "'" + (record ? " --record " + rec : std::string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  Digest got;
  std::string err;
  ASSERT_TRUE(digest_trace(csv, got, err)) << err;
  if (record) digest_recording(rec, got);
  const std::string what = config + ", " + span + " of virtual time";
  const std::string golden = dir + name + ".golden";
  const char* w = std::getenv("PLC_GOLDEN_WRITE");
  if (w && std::string(w) == "1") {
    if (!record) return;  // the recording run writes the digest
    std::ofstream(golden) << to_text(got, what);
    std::printf("wrote %s\n", golden.c_str());
  } else {
    Digest want;
    ASSERT_TRUE(from_text(plctest::read_file(golden), want)) << "malformed " << golden;
    ASSERT_GT(want.rows, 0u) << "missing or empty " << golden;
    if (!record) {  // the trace alone
      want.recording_bytes = 0;
      want.chunks.clear();
    }
    const std::string diff = differences(want, got);
    if (!diff.empty()) {
      ADD_FAILURE() << what << " differs from " << golden << ": " << diff
                    << "the trace and the recording are kept: " << csv << ", " << rec;
      return;
    }
  }
  std::filesystem::remove(csv);
  if (record) std::filesystem::remove(rec);
}

}  // namespace

// The demo tank: two tasks (1 ms and 10 ms), a first-order model, %M shared.
TEST(Golden, DemoCellTraceAndRecordingUnchanged) {
  check_cell("demo", "programs/demo/cell.yaml", "60s", "demo.vars");
}

// The filling cell on the sim plugin: E1, PR5510 and NORD models.
TEST(Golden, FillingCellTraceAndRecordingUnchanged) {
  check_cell("filling", "programs/filling_cell/cell.yaml", "60s", "filling.vars");
}

// The filling cell with the E1 and the NORD module over in-memory PROFINET.
TEST(Golden, FillingCellProfinetTraceAndRecordingUnchanged) {
  check_cell("filling_profinet", "programs/filling_cell/cell_profinet.yaml", "60s", "filling.vars");
}

// The conveyor: one 10 ms task, no devices.
TEST(Golden, ConveyorCellTraceAndRecordingUnchanged) {
  check_cell("conveyor", "programs/conveyor/cell.yaml", "60s", "conveyor.vars");
}

// The same runs with the trace alone (no hook: the scans copy and merge only
// the bound bytes); the trace must be the recording run's.
TEST(Golden, DemoCellTraceUnchangedWithoutRecording) {
  check_cell("demo", "programs/demo/cell.yaml", "60s", "demo.vars", false);
}

TEST(Golden, FillingCellTraceUnchangedWithoutRecording) {
  check_cell("filling", "programs/filling_cell/cell.yaml", "60s", "filling.vars", false);
}

TEST(Golden, FillingCellProfinetTraceUnchangedWithoutRecording) {
  check_cell("filling_profinet", "programs/filling_cell/cell_profinet.yaml", "60s", "filling.vars",
             false);
}

TEST(Golden, ConveyorCellTraceUnchangedWithoutRecording) {
  check_cell("conveyor", "programs/conveyor/cell.yaml", "60s", "conveyor.vars", false);
}
