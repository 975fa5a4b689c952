// The cell configuration as loaded from YAML: plain data, each item with the
// file position it came from, so every later check (unknown program type,
// address outside the image, unknown device in a binding) can still point
// at the line and key that caused it.
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "plc/io/byte_order.hpp"
#include "plc/io/model_params.hpp"
#include "plc/io/plugin.hpp"
#include "plc/io/process_image.hpp"
#include "plc/types.hpp"

namespace plc {

struct Mark {
  int line = 0, column = 0;  // 1-based; 0 = unknown
};

template <class T>
struct Item {
  T value{};
  Mark mark;
};

// `file:line:column: message`, and plcrun exits with code 2.
struct ConfigError : std::runtime_error {
  ConfigError(const std::string& file, Mark mark, const std::string& message);
  std::string file;
  Mark mark;
  std::string message;
};

struct Params {
  io::ModelParams values;
  std::map<std::string, Mark> marks;  // key -> where it is
  Mark mark;                          // the params block itself
};

// Ranges of the task keys (docs/config.md). A period from 1 us to a day,
// and a watchdog of at most 1000 periods: the watchdog time (at most 1000
// days) and every release time of a run stay far inside the int64
// nanoseconds of TIME.
inline constexpr TIME kMinPeriod = std::chrono::microseconds(1);
inline constexpr TIME kMaxPeriod = std::chrono::hours(24);
inline constexpr double kMaxWatchdog = 1000;

struct TaskConfig {
  Item<std::string> name;
  Item<TIME> period;
  Item<int> priority;
  std::vector<Item<std::string>> programs;
  Item<double> watchdog;  // multiple of the period; 0 = off
  Mark mark;
};

struct ProgramConfig {
  Item<std::string> name;
  Item<std::string> type;
  std::vector<std::pair<Item<std::string>, Item<std::string>>>
      bind;  // field path -> address/device
  std::vector<std::pair<Item<std::string>, Item<std::string>>> init;  // field path -> value
  Mark mark;
};

struct PluginConfig {
  Item<std::string> name;
  Item<std::string> type;
  Params params;
  Mark mark;
};

struct DeviceConfig {
  Item<std::string> name;
  Item<std::string> plugin;
  Item<std::string> model;
  Item<std::string> input;   // start address of its inputs, e.g. %IB0
  Item<std::string> output;  // start address of its outputs, e.g. %QB0
  Item<std::string> task;    // task that exchanges its data ("" = fastest)
  Params params;
  Mark mark;
};

struct SafeValueConfig {
  Item<std::string> address;
  Item<std::string> value;
};

// The `retain:` section (docs/config.md): where the cell keeps its RETAIN and
// PERSISTENT variables, how often they are saved, and which %M bytes are
// kept with them.
inline constexpr TIME kMinSaveEvery = std::chrono::milliseconds(1);
inline constexpr TIME kMaxSaveEvery = std::chrono::hours(1);
inline constexpr TIME kDefaultSaveEvery = std::chrono::milliseconds(100);

struct RetainMemoryRange {
  std::size_t byte = 0, count = 0;  // %MB<byte> .. %MB<byte+count-1>
  Mark mark;
};

// What a start does when the retain file's copies exist but none is valid
// (`on_damage:`): `cold` starts with initial values (reported), `stop`
// refuses to start. Unset: plcrun --warm stops, any other start goes cold.
enum class RetainOnDamage { Unset, Cold, Stop };

struct RetainConfig {
  bool present = false;
  Item<std::string> file;  // as written; resolved against the config's folder
  std::string path;        // the file to use
  Item<TIME> save_every{kDefaultSaveEvery, {}};
  std::vector<RetainMemoryRange> memory;
  Item<RetainOnDamage> on_damage{RetainOnDamage::Unset, {}};
  Mark mark;
};

// The `hmi:` section (docs/config.md): the LCM bridge to HMIs and plcctl
// (hmi-bridge/). Patterns are shell-style (`Cell.dose.*`, `%QW0`).
inline constexpr const char* kDefaultHmiUrl = "udpm://239.255.76.67:7667?ttl=0";
inline constexpr int kMaxHmiRate = 1000;  // snapshots per second

// The browser HMI served by plchmi (hmi-bridge/README.md "Web HMI"): where
// it listens, who may log in, and whether it may change anything.
struct WebConfig {
  bool present = false;
  Item<std::string> address{"127.0.0.1", {}};  // IPv4 or IPv6 literal
  Item<int> port{8080, {}};
  Item<bool> read_only{false, {}};  // values only: every write, force and stop refused
  // login: "none" (loopback addresses only), "key" (the HMI key_file's 64
  // hex digits are the password), or a password hash
  // "pbkdf2-sha256$ITERATIONS$SALT_HEX$HASH_HEX" (plchmi --hash-password).
  Item<std::string> login;
  // tls: {cert, key}: HTTPS and WSS only, with this PEM certificate (chain)
  // and private key; as written and resolved against the config's folder.
  bool tls = false;
  Item<std::string> tls_cert, tls_key;
  std::string tls_cert_path, tls_key_path;
  Mark mark;
};

struct HmiConfig {
  bool present = false;
  Item<std::string> url{kDefaultHmiUrl, {}};
  Item<std::string> prefix{"PLC", {}};  // channel names: PREFIX_VALUES, PREFIX_CMD, ...
  Item<int> rate{10, {}};               // full snapshots per second
  std::vector<Item<std::string>> publish, writable, forceable;
  Item<bool> stop_commands{false, {}};  // pause, step, continue, break allowed
  Item<std::string> key_file;           // as written
  std::string key_path;                 // resolved against the config's folder ("" = no key)
  // The bridge's own process (plchmi, hmi-bridge/README.md "Process layout"):
  // the user it runs as when plcrun runs as root ("" = nobody), and the
  // network namespace it joins (a name under /var/run/netns, or a path;
  // "" = plcrun's own).
  Item<std::string> user;
  Item<std::string> netns;
  WebConfig web;
  Mark mark;
};

struct CellConfig {
  std::string file;
  Item<std::string> cell;
  // Cell libraries to load before anything is resolved by name (key
  // `libraries:`), as absolute paths: a relative one is taken from the
  // config file's folder.
  std::vector<Item<std::string>> libraries;
  Item<io::ClockMode> clock{io::ClockMode::Virtual, {}};
  io::ImageSizes image;
  Item<io::ByteOrder> byte_order{io::ByteOrder::Big, {}};
  std::vector<TaskConfig> tasks;
  std::vector<ProgramConfig> programs;
  std::vector<PluginConfig> plugins;
  std::vector<DeviceConfig> devices;
  std::vector<SafeValueConfig> safe_values;
  RetainConfig retain;
  HmiConfig hmi;
  Mark image_mark;
};

// Parses a cell config file. Throws ConfigError for bad YAML, unknown keys,
// missing or ill-typed values, and structural errors (duplicate names,
// references to tasks/programs/plugins that are not declared).
CellConfig load_cell_config(const std::string& path);
CellConfig parse_cell_config(const std::string& yaml_text, const std::string& file_name);

}  // namespace plc
