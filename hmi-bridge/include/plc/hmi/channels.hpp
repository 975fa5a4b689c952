// The bridge's LCM channel names: PREFIX_<suffix>, PREFIX from the cell's
// `hmi: prefix:` (default PLC). LCM allows 63 characters; the prefix is at
// most 40 (cell_config.cpp).
#pragma once

#include <string>

namespace plc::hmi {

struct Channels {
  std::string values, trace, stats, diag, alarm, desc, cmd, reply;
  explicit Channels(const std::string& prefix)
      : values(prefix + "_VALUES"),
        trace(prefix + "_TRACE"),
        stats(prefix + "_STATS"),
        diag(prefix + "_DIAG"),
        alarm(prefix + "_ALARM"),
        desc(prefix + "_DESC"),
        cmd(prefix + "_CMD"),
        reply(prefix + "_REPLY") {}
};

}  // namespace plc::hmi
