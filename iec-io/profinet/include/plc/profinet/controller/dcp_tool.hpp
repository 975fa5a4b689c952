// The DCP tool behind `plcrun --pn-scan / --pn-set-name / --pn-set-ip`
// ("accessible devices"): Identify All on an interface and list who
// answered, and DCP Set of NameOfStation or IP suite on one device by MAC
// (IEC 61158-6-10 §4.3 DCP; fieldbus-masters.md §1 item 1).
//
// DcpScan is the I/O-free part (request frame, collecting answers, sorted
// result) so tests drive it over the in-memory link in virtual time;
// dcp_scan()/dcp_set() run it on a real port in real time (a command-line
// tool, never a scan thread); the *_command functions are the whole plcrun
// options, printing to the given streams and returning plcrun's exit code.
#pragma once

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "plc/profinet/link/ethernet_port.hpp"
#include "plc/profinet/wire/dcp.hpp"

namespace plc::profinet {

// ResponseDelayFactor of our Identify All: a device answers after
// (MAC mod 64) x 10 ms, so at most 630 ms after the request. The window
// adds 370 ms for the frames' way and a loaded host: 1 s in all.
inline constexpr std::uint16_t kScanResponseDelayFactor = 64;
inline constexpr std::chrono::milliseconds kScanWindow{1000};
// A Set is answered at once; asked up to 3 times, 500 ms apart (a Set of
// the same values twice is harmless).
inline constexpr int kSetAttempts = 3;
inline constexpr std::chrono::milliseconds kSetTimeout{500};

// One device that answered Identify.
struct DcpStation {
  Mac mac{};
  DcpIdentity id;
};

class DcpScan {
 public:
  DcpScan(const Mac& own, std::uint32_t xid) : own_(own), xid_(xid) {}
  // The Identify All request (multicast 01:0E:CF:00:00:00, FrameID 0xFEFE).
  [[nodiscard]] std::vector<std::uint8_t> request() const;
  // Takes an Identify response to us with our Xid; ignores other traffic,
  // counts undecodable answers in bad(). A MAC answering twice counts once
  // (the last answer).
  void on_frame(std::span<const std::uint8_t> frame);
  // The answers sorted by MAC.
  [[nodiscard]] std::vector<DcpStation> stations() const;
  [[nodiscard]] std::uint64_t bad() const { return bad_; }

 private:
  Mac own_;
  std::uint32_t xid_;
  std::vector<DcpStation> stations_;
  std::uint64_t bad_ = 0;
};

// "device", "controller", "device+controller", ... (DeviceRole bits).
std::string role_text(std::uint8_t role);
// One line per device:
//   02:00:00:00:00:02  conveyor  ip 10.88.1.2/255.255.255.0 gw 0.0.0.0
//   vendor 0x0fff device 0x0e01  role device  type "softplc pndevsim"
// (one line; an unnamed device shows name "(none)").
std::string format_station(const DcpStation& s);
// The whole listing: a count line and the devices, or the "no PROFINET
// devices answered on IFACE within N ms" line.
std::string format_scan(std::span<const DcpStation> stations, std::string_view iface,
                        std::chrono::milliseconds window);

// Sends Identify All on `port` and collects answers for `window` (real
// time, steady clock).
std::vector<DcpStation> dcp_scan(EthernetPort& port,
                                 std::chrono::milliseconds window = kScanWindow);

struct DcpSetOutcome {
  bool answered = false;
  std::vector<DcpSetResult> results;  // the device's Control/Response blocks
};
// Sends the Set to `device` (unicast, FrameID 0xFEFD) and waits for its
// answer; kSetAttempts tries of kSetTimeout.
DcpSetOutcome dcp_set(EthernetPort& port, const Mac& device, const DcpSetRequest& req);

// "IP[/PREFIX[/GATEWAY]]": prefix 1..32 (default 24), gateway default
// 0.0.0.0 (none). nullopt and `why` when malformed.
std::optional<DcpIpSuite> parse_ip_suite(std::string_view s, std::string& why);

// The plcrun options. Exit codes as plcrun's: 0 done; 1 the interface
// cannot be opened (missing, no CAP_NET_RAW), the device did not answer
// or refused the Set; 2 a bad argument (nothing sent).
int pn_scan_command(const std::string& iface, std::ostream& out, std::ostream& err);
int pn_set_name_command(const std::string& iface, const std::string& mac, const std::string& name,
                        std::ostream& out, std::ostream& err);
int pn_set_ip_command(const std::string& iface, const std::string& mac, const std::string& ip,
                      std::ostream& out, std::ostream& err);

}  // namespace plc::profinet
