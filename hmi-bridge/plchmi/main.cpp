// plchmi: the HMI bridge's process (hmi-bridge/README.md, "Process
// layout"). plcrun starts it with the shared memory and the doorbell as
// inherited descriptors, unprivileged, and starts it again when it dies:
//   plchmi --state-fd 3 --control-fd 4 --doorbell-fd 5
// With hmi: web: it also serves the browser HMI ("Web HMI").
//   plchmi --hash-password
// reads a password on stdin and prints the hash for hmi: web: login.
// It ends on SIGTERM or SIGINT (exit 0). Exit 78 (EX_CONFIG): it cannot
// start (the url cannot be opened, the shared memory is not plcrun's, the
// web address cannot be bound); 2: bad usage.
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <memory>
#include <string>

#include "plc/hmi/bridge.hpp"
#include "plc/hmi/web/web_auth.hpp"
#include "plc/hmi/web/web_server.hpp"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);  // so async-signal-safe

extern "C" void on_signal(int) { g_stop.store(true); }

int usage() {
  std::fprintf(stderr,
               "usage: plchmi --state-fd N --control-fd N [--doorbell-fd N]\n"
               "       (plcrun starts it for a cell with an hmi: section)\n"
               "       plchmi --hash-password   (a password on stdin -> hmi: web: login)\n");
  return 2;
}

int hash_password() {
  std::string password;
  if (!std::getline(std::cin, password) || password.empty()) {
    std::fprintf(stderr, "plchmi: no password on stdin\n");
    return 2;
  }
  std::printf("%s\n", plc::hmi::web::hash_password(password).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--hash-password") return hash_password();
  int state = -1, control = -1, doorbell = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage();
    char* end = nullptr;
    const long fd = std::strtol(argv[++i], &end, 10);
    if (*end || fd < 0 || fd > 1024) return usage();
    if (a == "--state-fd")
      state = int(fd);
    else if (a == "--control-fd")
      control = int(fd);
    else if (a == "--doorbell-fd")
      doorbell = int(fd);
    else
      return usage();
  }
  if (state < 0 || control < 0) return usage();
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);  // a browser that went away is an error code, not a signal
  try {
    std::string err;
    auto regions = plc::hmi::ipc::Regions::attach(state, control, err);
    if (!regions) {
      std::fprintf(stderr, "plchmi: %s\n", err.c_str());
      return 78;
    }
    const plc::hmi::ipc::Settings settings = regions->settings();
    plc::hmi::Bridge bridge(std::move(regions), doorbell);
    std::unique_ptr<plc::hmi::web::WebServer> web;
    if (settings.web_port != 0) {
      const plc::hmi::web::WebOptions o = plc::hmi::web::web_options(settings);
      web = std::make_unique<plc::hmi::web::WebServer>(bridge, o);
      bridge.set_tap(web.get());
      web->start();
      std::fprintf(stderr, "plchmi: web HMI on %s://%s%s%s:%d/\n",
                   o.tls_cert_pem.empty() ? "http" : "https",
                   o.address.find(':') != std::string::npos ? "[" : "", o.address.c_str(),
                   o.address.find(':') != std::string::npos ? "]" : "", web->port());
    }
    bridge.publish_description();
    bridge.run(g_stop);
    bridge.set_tap(nullptr);
    if (web) web->stop();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plchmi: %s\n", e.what());
    return 78;
  }
  return 0;
}
