// The two shared-memory regions between plcrun and plchmi, byte for byte
// (hmi-bridge/README.md, "Process layout"). Offsets are from the start of
// their region; every section is 64-byte aligned.
//
// state (plcrun writes; plchmi maps it read-only):
//   StateHeader | Settings | cell layout (cell_layout.hpp) | per task: a
//   SlotHeader and its values | statistics, diagnostics, outage notes
//   (seqlock.hpp blocks, notes.hpp) | the reply ring's records
// control (both write; plcrun trusts nothing in it):
//   ControlHeader (plchmi's ring positions, its snapshot requests, its
//   counters) | the command ring's records
//
// A snapshot: plchmi asks for task k's values by raising requests[k]; the
// task's scan thread, at the end of its next scan, sees a request it has
// not served (one atomic load, compared with a number it keeps itself),
// copies the values into the slot's buffer, notes scan, PLC time and copy
// time, and stores the request's number in SlotHeader::filled (release).
// plchmi reads the values once filled equals its request. The scan thread
// never waits, never makes a system call for it (CLOCK_REALTIME is the
// vDSO), and whatever plchmi writes into requests[k], it does no more than
// copy the published values at a scan end.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

namespace plc::hmi::ipc {

inline constexpr std::uint32_t kStateMagic = 0x53484c50;    // "PLHS"
inline constexpr std::uint32_t kControlMagic = 0x43484c50;  // "PLHC"
inline constexpr std::uint32_t kVersion = 4;
inline constexpr std::size_t kMaxSlots = 64;  // tasks with published variables
inline constexpr std::uint32_t kCommandCapacity = 32;
inline constexpr std::uint32_t kReplyCapacity = 16;
inline constexpr std::size_t kAlign = 64;

constexpr std::size_t align_up(std::size_t n, std::size_t a = kAlign) {
  return (n + a - 1) / a * a;
}

struct Section {
  std::uint64_t offset = 0, size = 0;
};

// plcrun's counters of what it did with the command ring.
struct HostCounters {
  std::atomic<std::uint64_t> served{0};        // records that reached the debugger
  std::atomic<std::uint64_t> refused{0};       // records refused by plcrun (any Reason but Ok)
  std::atomic<std::uint64_t> malformed{0};     // ... of them Malformed, Stale or BadOperand
  std::atomic<std::uint64_t> skipped{0};       // command ring positions that were not plausible
  std::atomic<std::uint64_t> replies_lost{0};  // reply ring full
};

struct StateHeader {
  std::uint32_t magic = kStateMagic, version = kVersion;
  std::uint64_t size = 0;
  std::uint64_t boot_epoch = 0;  // getrandom() at plcrun's start
  std::uint64_t host_pid = 0;
  // Bumped by every build of the runtime (goto, restart): odd while plcrun
  // rewrites the layout, even when it is settled.
  std::atomic<std::uint64_t> generation{0};
  std::atomic<std::uint64_t> layout_size{0};  // bytes of the layout section in use
  Section settings, layout, slots, stats, diag, outages, replies;
  std::uint32_t reply_capacity = kReplyCapacity;
  std::uint32_t slot_count = 0;
  std::atomic<std::uint64_t> command_tail{0};  // plcrun reads the command ring up to here
  std::atomic<std::uint64_t> reply_head{0};    // plcrun wrote replies up to here
  HostCounters host;
};

// Bounds of hmi: web: tls: files (with their NUL): a chain of a few
// certificates, an EC or RSA (up to 4096 bits) key.
inline constexpr std::size_t kMaxTlsCertPem = 16384;
inline constexpr std::size_t kMaxTlsKeyPem = 4096;

// The hmi: settings plchmi needs; strings NUL-terminated.
struct Settings {
  char url[256] = {};
  char prefix[64] = {};
  char cell_file[256] = {};
  std::int32_t url_line = 0, url_column = 0;  // of the url in the cell file (errors)
  std::int32_t rate = 10;
  std::uint8_t stop_commands = 0;
  std::uint8_t has_key = 0;
  std::uint8_t pad[2] = {};
  std::uint8_t key[32] = {};
  // hmi: web: (cell_config.hpp WebConfig); web_port 0: no web server.
  std::uint16_t web_port = 0;
  std::uint8_t web_read_only = 0;
  std::uint8_t web_login = 0;  // WebLogin
  char web_address[64] = {};
  char web_password_hash[256] = {};  // web_login == Hash
  // hmi: web: tls: the PEM texts plcrun read and checked (tls_files.hpp);
  // web_tls_cert[0] == 0: plain HTTP. In the state region, which only
  // plcrun and plchmi map (a memfd, as the HMI key above).
  char web_tls_cert[kMaxTlsCertPem] = {};
  char web_tls_key[kMaxTlsKeyPem] = {};
};

enum class WebLogin : std::uint8_t { None = 0, Key = 1, Hash = 2 };

struct SlotHeader {
  std::atomic<std::uint64_t> filled{0};  // the request these values answer
  // Written before `filled`, read after it.
  std::uint64_t scan = 0;  // the task's scan count at the copy (1 = its first)
  std::int64_t plc_time_ns = 0;
  std::int64_t copy_utime = 0;  // CLOCK_REALTIME at the copy, microseconds
};

// plchmi's own counters, for plcrun's summary (numbers only, never trusted
// for anything else).
struct BridgeCounters {
  std::atomic<std::uint64_t> published{0}, dropped{0}, commands{0}, refused{0}, bad_tag{0},
      replayed{0}, stale{0}, malformed{0};
};

struct ControlHeader {
  std::uint32_t magic = kControlMagic, version = kVersion;
  std::uint64_t size = 0;
  Section commands;
  std::uint32_t command_capacity = kCommandCapacity;
  std::uint32_t pad = 0;
  std::atomic<std::uint64_t> command_head{0};       // plchmi wrote commands up to here
  std::atomic<std::uint64_t> reply_tail{0};         // plchmi read replies up to here
  std::atomic<std::uint64_t> announced_outages{0};  // outage notes plchmi has published
  std::atomic<std::uint64_t> bridge_pid{0};
  BridgeCounters bridge;
  std::atomic<std::uint64_t> requests[kMaxSlots];  // per slot: the snapshot asked for
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

}  // namespace plc::hmi::ipc
