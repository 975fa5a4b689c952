// Who plchmi runs as, and in which network namespace (the cell's hmi: user
// and netns keys, docs/config.md), resolved when plcrun starts so that a
// wrong name is a config error at its line and not a failure at the first
// start of the bridge.
//   plcrun as root: plchmi drops to `user` (default nobody, its group);
//     `user: root` keeps UID 0 (still without any capability) and plcrun
//     says so.
//   plcrun as another user: plchmi runs as that user; naming another one
//     is an error (only root can switch).
//   netns: /var/run/netns/NAME (as `ip netns add` makes them) or a path
//     such as /proc/PID/ns/net; joining needs root (CAP_SYS_ADMIN).
#pragma once

#include <sys/types.h>

#include <string>

#include "plc/cell_config.hpp"

namespace plc::hmi {

class Privileges {
 public:
  Privileges() = default;
  ~Privileges();
  Privileges(Privileges&& o) noexcept;
  Privileges& operator=(Privileges&& o) noexcept;
  Privileges(const Privileges&) = delete;
  Privileges& operator=(const Privileges&) = delete;

  bool change_user = false;  // plcrun is root: setresuid/setresgid in the child
  uid_t uid = 0;
  gid_t gid = 0;
  std::string user;   // the name, for messages
  int netns_fd = -1;  // open namespace, or -1
};

// Throws ConfigError (file:line:col of the key) for an unknown user, a
// switch plcrun cannot make, a namespace that cannot be opened or joined.
Privileges resolve_privileges(const HmiConfig& cfg, const std::string& file);

// plchmi beside the running executable (build/bin/, or the installed bin/).
std::string default_plchmi_path();

}  // namespace plc::hmi
