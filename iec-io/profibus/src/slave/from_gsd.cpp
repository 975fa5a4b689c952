#include "plc/profibus/slave/from_gsd.hpp"

namespace plc::profibus::slave {

SlaveConfig slave_config_from_gsd(const gsd::Gsd& g, std::uint8_t address, std::size_t in_bytes,
                                  std::size_t out_bytes) {
  SlaveConfig c;
  c.address = address;
  c.ident = g.ident();
  c.input_bytes = in_bytes;
  c.output_bytes = out_bytes;
  c.freeze_supported = g.freeze_supported();
  c.sync_supported = g.sync_supported();
  c.user_prm_len = static_cast<std::size_t>(g.number("User_Prm_Data_Len", 0));
  c.max_diag_len = g.max_diag_len();
  if (g.modular()) {
    for (const gsd::Module& m : g.modules)
      if (m.cfg.size() == 1) c.modules.push_back(m.cfg[0]);
    c.max_modules = g.max_modules();
  } else if (!g.modules.empty()) {
    c.cfg = g.modules.front().cfg;
  }
  return c;
}

}  // namespace plc::profibus::slave
