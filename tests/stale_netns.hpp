// Network namespaces of the tests' own are named "<prefix><pid>_<n>" and
// deleted when the test ends; one left by a test process that died (a
// crash, a kill at ctest's timeout) is deleted the next time a test makes
// one: no process of that pid runs any more.
#pragma once

#include <dirent.h>
#include <signal.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "runtime/test_helpers.hpp"

namespace plctest {

inline void delete_stale_netns(const std::string& prefix) {
  DIR* d = ::opendir("/run/netns");
  if (!d) return;
  std::vector<std::string> stale;
  for (int i = 0; i < 10000; ++i) {
    dirent* e = ::readdir(d);
    if (!e) break;
    const std::string name = e->d_name;
    if (name.rfind(prefix, 0) != 0) continue;
    const int pid = std::atoi(name.c_str() + prefix.size());
    if (pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH) stale.push_back(name);
  }
  ::closedir(d);
  // Names of our own making (prefix, digits, '_'): nothing to quote.
  for (const auto& n : stale) (void)run_command("ip netns delete '" + n + "'");
}

}  // namespace plctest
