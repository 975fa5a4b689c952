#include "plc/hmi/host_privileges.hpp"

#include <fcntl.h>
#include <pwd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>
#include <vector>

namespace plc::hmi {

Privileges::~Privileges() {
  if (netns_fd >= 0) close(netns_fd);
}

Privileges::Privileges(Privileges&& o) noexcept
    : change_user(o.change_user),
      uid(o.uid),
      gid(o.gid),
      user(std::move(o.user)),
      netns_fd(std::exchange(o.netns_fd, -1)) {}

Privileges& Privileges::operator=(Privileges&& o) noexcept {
  if (this != &o) {
    if (netns_fd >= 0) close(netns_fd);
    change_user = o.change_user;
    uid = o.uid;
    gid = o.gid;
    user = std::move(o.user);
    netns_fd = std::exchange(o.netns_fd, -1);
  }
  return *this;
}

namespace {

// getpwnam_r into a buffer of our own (getpwnam's is static).
bool lookup(const std::string& name, uid_t& uid, gid_t& gid) {
  std::vector<char> buf(16384);
  passwd pw{};
  passwd* found = nullptr;
  if (getpwnam_r(name.c_str(), &pw, buf.data(), buf.size(), &found) != 0 || !found) return false;
  uid = found->pw_uid;
  gid = found->pw_gid;
  return true;
}

}  // namespace

Privileges resolve_privileges(const HmiConfig& cfg, const std::string& file) {
  Privileges p;
  const bool root = geteuid() == 0;
  const Mark user_mark = cfg.user.value.empty() ? cfg.mark : cfg.user.mark;
  if (root) {
    p.user = cfg.user.value.empty() ? "nobody" : cfg.user.value;
    if (!lookup(p.user, p.uid, p.gid))
      throw ConfigError(file, user_mark,
                        "key 'user': no user '" + p.user +
                            "' on this host (plchmi, the HMI bridge, runs as it when plcrun runs "
                            "as root)");
    p.change_user = true;
  } else {
    p.uid = geteuid();
    p.gid = getegid();
    if (!cfg.user.value.empty()) {
      uid_t uid = 0;
      gid_t gid = 0;
      if (!lookup(cfg.user.value, uid, gid))
        throw ConfigError(file, cfg.user.mark, "key 'user': no user '" + cfg.user.value + "'");
      if (uid != p.uid)
        throw ConfigError(file, cfg.user.mark,
                          "key 'user': plcrun runs as UID " + std::to_string(p.uid) +
                              ", not as root: it cannot start plchmi as '" + cfg.user.value +
                              "' (leave the key out, or run plcrun as root)");
    }
    p.user = cfg.user.value;
  }
  if (!cfg.netns.value.empty()) {
    const std::string& ns = cfg.netns.value;
    const std::string path = ns[0] == '/' ? ns : "/var/run/netns/" + ns;
    if (!root)
      throw ConfigError(file, cfg.netns.mark,
                        "key 'netns': joining a network namespace needs plcrun to run as root");
    p.netns_fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (p.netns_fd < 0)
      throw ConfigError(file, cfg.netns.mark,
                        "key 'netns': cannot open " + path + ": " + std::strerror(errno) +
                            (ns[0] == '/' ? "" : " (ip netns add " + ns + " makes it)"));
  }
  return p;
}

std::string default_plchmi_path() {
  std::vector<char> buf(4096);
  const ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0) return "plchmi";
  std::string exe(buf.data(), std::size_t(n));
  const auto slash = exe.rfind('/');
  return (slash == std::string::npos ? std::string() : exe.substr(0, slash + 1)) + "plchmi";
}

}  // namespace plc::hmi
