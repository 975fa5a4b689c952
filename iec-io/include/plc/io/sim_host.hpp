// What the simulator hosts share (dnslave, dpslavesim, pndevsim: device
// models behind a fieldbus slave stack, as a process of their own): the
// command line `TOOL CONFIG.yaml [--for DURATION]`, the YAML config's
// checks with line:column in every message and its loading, the monotonic clock of their
// loops, the signals that end a run or toggle "silent" on every slave, and
// main()'s last word on an exception.
//
// Header-only on yaml-cpp: only those executables include it, and they
// link yaml-cpp themselves (plc_io does not).
#pragma once

#include <yaml-cpp/yaml.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>

#include "plc/config_path.hpp"
#include "plc/iec_literal.hpp"
#include "plc/realtime_thread.hpp"

namespace plc::io::sim_host {

using plc::mono_ns;

// A bad config: "LINE:COLUMN: message" (the caller prefixes the file).
struct ConfigError : std::runtime_error {
  ConfigError(const YAML::Node& n, const std::string& msg)
      : std::runtime_error(n.Mark().line >= 0 ? std::to_string(n.Mark().line + 1) + ":" +
                                                    std::to_string(n.Mark().column + 1) + ": " + msg
                                              : msg) {}
};

// map[key] as a number in [min, max], `def` when the key is absent.
template <class T>
T get_number(const YAML::Node& map, const char* key, T def, T min, T max) {
  const YAML::Node n = map[key];
  if (!n) return def;
  T v{};
  try {
    v = n.as<T>();
  } catch (const YAML::Exception&) {
    throw ConfigError(n, std::string("key '") + key + "': not a number");
  }
  if (v < min || v > max)
    throw ConfigError(n, std::string("key '") + key + "': out of range [" + std::to_string(min) +
                             ", " + std::to_string(max) + "]");
  return v;
}

// map[key] as an IEC duration (2ms, T#1s), `def` when the key is absent.
inline std::chrono::nanoseconds get_time(const YAML::Node& map, const char* key,
                                         std::chrono::nanoseconds def) {
  const YAML::Node v = map[key];
  if (!v) return def;
  const auto t = plc::parse_iec_time(v.as<std::string>());
  if (!t || t->count() < 0)
    throw ConfigError(v, std::string("key '") + key + "': not a duration (e.g. 2ms, T#1s)");
  return *t;
}

// A map whose keys are all among `known`.
inline void reject_unknown(const YAML::Node& map, std::initializer_list<const char*> known) {
  if (!map.IsMap()) throw ConfigError(map, "expected a map");
  for (const auto& kv : map) {
    const std::string k = kv.first.as<std::string>();
    bool ok = false;
    for (const char* q : known) ok = ok || k == q;
    if (!ok) throw ConfigError(kv.first, "unknown key '" + k + "'");
  }
}

struct Args {
  std::string config;
  std::int64_t run_ns = -1;  // --for; -1: until a signal
};

// `tool CONFIG.yaml [--for DURATION]`; nullopt after a message on stderr
// (the tool's exit code 2).
inline std::optional<Args> parse_args(const char* tool, int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CONFIG.yaml [--for DURATION]\n", tool);
    return std::nullopt;
  }
  Args a;
  a.config = argv[1];
  for (int i = 2; i < argc; i += 2) {
    const std::string opt = argv[i];
    if (opt != "--for") {
      std::fprintf(stderr, "%s: unknown option '%s'\n", tool, argv[i]);
      return std::nullopt;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "%s: --for: needs a duration (e.g. 10s)\n", tool);
      return std::nullopt;
    }
    const auto t = plc::parse_iec_time(argv[i + 1]);
    if (!t || t->count() < 0) {
      std::fprintf(stderr, "%s: --for: bad duration '%s'\n", tool, argv[i + 1]);
      return std::nullopt;
    }
    a.run_ns = t->count();
  }
  return a;
}

// Set from signal handlers: SIGTERM/SIGINT end the run, each SIGUSR1
// toggles "silent" on every slave (a pulled plug without killing the
// process). A loop compares g_toggle_silent with the count it acted on.
inline std::atomic<bool> g_stop{false};
inline std::atomic<int> g_toggle_silent{0};

inline void install_signals() {
  std::signal(SIGTERM, [](int) { g_stop = true; });
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGUSR1, [](int) { g_toggle_silent.fetch_add(1); });
}

// Reads the tool's config FILE and builds what it describes: load(root).
// Every error of it goes to stderr and gives false (the tool's exit code
// 2): a file it cannot read ("FILE: why"), a ConfigError
// ("FILE:LINE:COLUMN: message"), yaml-cpp's own ("FILE: message"), any
// other ("TOOL: message": a bus, line or interface that cannot be opened).
template <class Load>
bool load_config(const char* tool, const std::string& file, Load&& load) {
  if (const std::string why = plc::readable_file_problem(file); !why.empty()) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), why.c_str());
    return false;
  }
  try {
    load(YAML::LoadFile(file));
    return true;
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "%s:%s\n", file.c_str(), e.what());
  } catch (const YAML::Exception& e) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
  }
  return false;
}

// The tool's main(): run(argc, argv)'s exit code. Nothing ends the tool
// with an uncaught exception: what escapes run() (the bus or line failing
// while it runs) is "TOOL: what" on stderr and exit code 1.
inline int guarded_main(const char* tool, int (*run)(int, char**), int argc, char** argv) noexcept {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: an unknown error\n", tool);
  }
  return 1;
}

}  // namespace plc::io::sim_host
