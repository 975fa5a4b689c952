// Fuzz target: the recording reader (plc/debug/recording.hpp). The input is
// written to a file and replayed on the filling cell, as `plcrun --replay`
// does; a damaged recording must end in a refusal (std::runtime_error from
// the constructor) or an error/mismatch report, never a crash, a huge
// allocation or a hang. Seeds: recordings of the filling cell, from scan 0
// and from the middle of a session (with a state snapshot); scripts/fuzz
// records fresh ones with the build's own plcrun before each run, so the
// seeds follow the file format.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "fuzz_cell.hpp"
#include "plc/debug/recording.hpp"
#include "plc/runtime.hpp"

namespace {
constexpr int kMaxScans = 5000;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string file = "/tmp/plc_fuzz_recording_" + std::to_string(::getpid()) + ".rec";
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);

  plc::Runtime rt(plc::fuzz::filling_cell());
  try {
    plc::debug::Replayer replay(rt, file);
    rt.start(plc::io::ClockMode::Virtual);
    for (int i = 0; i < kMaxScans && replay.step(); ++i) {
    }
    rt.finish();
  } catch (const std::runtime_error&) {
  }
  return 0;
}
