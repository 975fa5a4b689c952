// Fuzz target: the ASCII GSD parser (iec-io/profibus/gsd). Any text either
// parses or is refused with GsdError naming a line within the text
// (property); a parsed file's modules have the I/O sizes of their Cfg
// bytes, and its derived values (numbers, MaxTsdr per baud rate, the user
// parameter data for every module) are computed or refused with GsdError.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/fdl/timing.hpp"
#include "plc/profibus/gsd/gsd.hpp"

using namespace plc::profibus;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::size_t lines = 1;
  for (const char c : text) lines += c == '\n';
  gsd::Gsd g;
  try {
    g = gsd::parse_gsd(text, "fuzz.gsd");
  } catch (const gsd::GsdError& e) {
    if (e.line > lines) std::abort();
    return 0;
  }
  try {
    std::vector<const gsd::Module*> all;
    for (const gsd::Module& m : g.modules) {
      const auto s = dp::cfg_sizes(m.cfg);
      if (!s || s->input_bytes != m.input_bytes || s->output_bytes != m.output_bytes) std::abort();
      all.push_back(&m);
    }
    (void)g.ident();
    (void)g.max_modules();
    (void)g.min_slave_interval();
    for (const auto& p : fdl::baud_profiles()) {
      (void)g.baud_supported(p.gsd_suffix);
      (void)g.max_tsdr(p.gsd_suffix);
    }
    if (all.size() <= 8) (void)g.user_prm_data(all);
  } catch (const gsd::GsdError& e) {
    if (e.line > lines) std::abort();
  }
  return 0;
}
