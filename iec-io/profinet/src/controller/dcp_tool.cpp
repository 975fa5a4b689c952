#include "plc/profinet/controller/dcp_tool.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <ostream>
#include <random>

#include "plc/profinet/link/open_link.hpp"

namespace plc::profinet {

namespace {

using Clock = std::chrono::steady_clock;

// A fresh Xid per request, so answers to an earlier tool run are not taken.
std::uint32_t new_xid() {
  std::random_device rd;
  return rd();
}

std::string hex4(std::uint16_t v) {
  char b[8];
  std::snprintf(b, sizeof b, "0x%04x", v);
  return b;
}

std::string ip_text(const DcpIpSuite& ip) {
  return to_string(Ipv4{ip.ip}) + "/" + to_string(Ipv4{ip.netmask}) + " gw " +
         to_string(Ipv4{ip.gateway});
}

const char* set_error_text(std::uint8_t e) {
  switch (e) {
    case dcp::kErrorOk:
      return "ok";
    case dcp::kErrorOptionUnsupported:
      return "option not supported";
    case dcp::kErrorSuboptionUnsupported:
      return "suboption not supported";
    case dcp::kErrorSuboptionNotSet:
      return "suboption not set";
    case dcp::kErrorResource:
      return "resource error";
    case dcp::kErrorSetNotPossible:
      return "set not possible (local reasons, e.g. the device is in data exchange)";
    default:
      return "unknown error";
  }
}

// Opens the interface; on failure says why on `err` (LinkError's text names
// the missing interface or CAP_NET_RAW).
std::unique_ptr<EthernetPort> open_port(const std::string& iface, const char* option,
                                        std::ostream& err) {
  try {
    return open_ethernet(iface);
  } catch (const LinkError& e) {
    err << "plcrun: " << option << ": " << e.what() << "\n";
    return nullptr;
  }
}

// The common part of --pn-set-name and --pn-set-ip once the request is
// valid: open, send, check every result.
int run_set(const std::string& iface, const Mac& mac, const DcpSetRequest& req, const char* option,
            const std::string& what, std::ostream& out, std::ostream& err) {
  auto port = open_port(iface, option, err);
  if (!port) return 1;
  const DcpSetOutcome o = dcp_set(*port, mac, req);
  if (!o.answered) {
    err << "plcrun: " << option << ": no DCP Set answer from " << to_string(mac) << " on " << iface
        << " (" << kSetAttempts << " tries of " << kSetTimeout.count()
        << " ms; --pn-scan lists the devices)\n";
    return 1;
  }
  bool ok = !o.results.empty();
  for (const auto& r : o.results) {
    if (r.error == dcp::kErrorOk) continue;
    ok = false;
    err << "plcrun: " << option << ": " << to_string(mac) << " refused the Set (option "
        << int{r.option} << "/" << int{r.suboption} << "): error " << int{r.error} << ", "
        << set_error_text(r.error) << "\n";
  }
  if (o.results.empty())
    err << "plcrun: " << option << ": " << to_string(mac) << " answered without a result\n";
  if (!ok) return 1;
  out << "plcrun: " << to_string(mac) << ": " << what << " (stored permanently)\n";
  return 0;
}

std::optional<Mac> parse_mac_arg(const std::string& s, const char* option, std::ostream& err) {
  const auto mac = parse_mac(s);
  if (!mac)
    err << "plcrun: " << option << ": '" << s << "' is not a MAC address (02:00:00:00:00:01)\n";
  return mac;
}

}  // namespace

// ---------------------------------------------------------------- scan

std::vector<std::uint8_t> DcpScan::request() const {
  return encode_dcp_identify_request(own_, xid_, std::nullopt, kScanResponseDelayFactor);
}

void DcpScan::on_frame(std::span<const std::uint8_t> frame) {
  PnFrameView v;
  if (!decode_pn_frame(frame, v) || v.frame_id != frame_id::kDcpIdentifyResponse || v.dst != own_)
    return;
  DcpMessage m;
  DcpIdentity id;
  if (!decode_dcp(v.frame_id, v.pdu, m) || m.service_id != dcp::kServiceIdentify ||
      m.service_type != dcp::kTypeResponseSuccess || !identity_from(m, id)) {
    ++bad_;
    return;
  }
  if (m.xid != xid_) return;  // an answer to another request
  const auto it = std::find_if(stations_.begin(), stations_.end(),
                               [&](const DcpStation& s) { return s.mac == v.src; });
  if (it != stations_.end())
    it->id = std::move(id);
  else
    stations_.push_back({v.src, std::move(id)});
}

std::vector<DcpStation> DcpScan::stations() const {
  auto out = stations_;
  std::sort(out.begin(), out.end(),
            [](const DcpStation& a, const DcpStation& b) { return a.mac < b.mac; });
  return out;
}

std::string role_text(std::uint8_t role) {
  static constexpr const char* kBits[] = {"device", "controller", "multidevice", "supervisor"};
  std::string s;
  for (int i = 0; i < 4; ++i)
    if (role & (1u << i)) s += (s.empty() ? "" : "+") + std::string(kBits[i]);
  if (role & 0xF0 || s.empty()) s += (s.empty() ? "" : "+") + hex4(role);
  return s;
}

std::string format_station(const DcpStation& s) {
  std::string line = to_string(s.mac) + "  " +
                     (s.id.station_name.empty() ? "(none)" : s.id.station_name) + "  ip " +
                     ip_text(s.id.ip) + "  vendor " + hex4(s.id.vendor_id) + " device " +
                     hex4(s.id.device_id) + "  role " + role_text(s.id.device_role);
  if (!s.id.type_of_station.empty()) line += "  type \"" + s.id.type_of_station + "\"";
  return line;
}

std::string format_scan(std::span<const DcpStation> stations, std::string_view iface,
                        std::chrono::milliseconds window) {
  const std::string where =
      " on " + std::string(iface) + " within " + std::to_string(window.count()) + " ms";
  if (stations.empty()) return "no PROFINET devices answered" + where + "\n";
  std::string out = std::to_string(stations.size()) + " PROFINET device" +
                    (stations.size() == 1 ? "" : "s") + " answered" + where + ":\n";
  for (const auto& s : stations) out += format_station(s) + "\n";
  return out;
}

std::vector<DcpStation> dcp_scan(EthernetPort& port, std::chrono::milliseconds window) {
  DcpScan scan(port.mac(), new_xid());
  const auto end = Clock::now() + window;
  (void)port.send(scan.request());
  std::vector<std::uint8_t> buf(kMaxFrameLength);
  // Bounded by the window and by a frame count (a flooded segment).
  for (int i = 0; i < 100000; ++i) {
    const auto left = end - Clock::now();
    if (left <= Clock::duration::zero()) break;
    const std::size_t n = port.receive(buf, left);
    if (n) scan.on_frame(std::span<const std::uint8_t>(buf.data(), n));
  }
  return scan.stations();
}

// ---------------------------------------------------------------- set

DcpSetOutcome dcp_set(EthernetPort& port, const Mac& device, const DcpSetRequest& req) {
  DcpSetOutcome o;
  std::vector<std::uint8_t> buf(kMaxFrameLength);
  for (int attempt = 0; attempt < kSetAttempts; ++attempt) {
    const std::uint32_t xid = new_xid();
    (void)port.send(encode_dcp_set_request(device, port.mac(), xid, req));
    const auto end = Clock::now() + kSetTimeout;
    for (int i = 0; i < 100000; ++i) {
      const auto left = end - Clock::now();
      if (left <= Clock::duration::zero()) break;
      const std::size_t n = port.receive(buf, left);
      PnFrameView v;
      DcpMessage m;
      if (!n || !decode_pn_frame(std::span<const std::uint8_t>(buf.data(), n), v) ||
          v.frame_id != frame_id::kDcpGetSet || v.src != device || v.dst != port.mac() ||
          !decode_dcp(v.frame_id, v.pdu, m) || m.service_id != dcp::kServiceSet ||
          m.service_type == dcp::kTypeRequest || m.xid != xid)
        continue;
      o.answered = true;
      if (!set_results_from(m, o.results)) o.results.clear();
      return o;
    }
  }
  return o;
}

std::optional<DcpIpSuite> parse_ip_suite(std::string_view s, std::string& why) {
  std::string_view parts[3];
  int count = 0;
  for (std::size_t start = 0;; ++count) {
    if (count == 3) {
      why = "more than IP/PREFIX/GATEWAY";
      return std::nullopt;
    }
    const std::size_t slash = s.find('/', start);
    parts[count] = s.substr(start, slash == std::string_view::npos ? s.npos : slash - start);
    if (slash == std::string_view::npos) {
      ++count;
      break;
    }
    start = slash + 1;
  }
  DcpIpSuite suite;
  const auto ip = parse_ipv4(parts[0]);
  if (!ip || ip->host_order == 0) {
    why = "'" + std::string(parts[0]) + "' is not an IPv4 address";
    return std::nullopt;
  }
  suite.ip = ip->host_order;
  unsigned prefix = 24;
  if (count > 1) {
    const auto* first = parts[1].data();
    const auto* last = first + parts[1].size();
    const auto r = std::from_chars(first, last, prefix);
    if (parts[1].empty() || r.ec != std::errc{} || r.ptr != last || prefix < 1 || prefix > 32) {
      why = "prefix '" + std::string(parts[1]) + "' is not 1..32";
      return std::nullopt;
    }
  }
  suite.netmask = prefix == 32 ? 0xFFFFFFFFu : ~(0xFFFFFFFFu >> prefix);
  if (count > 2) {
    const auto gw = parse_ipv4(parts[2]);
    if (!gw) {
      why = "gateway '" + std::string(parts[2]) + "' is not an IPv4 address";
      return std::nullopt;
    }
    suite.gateway = gw->host_order;
  }
  return suite;
}

// ---------------------------------------------------------------- commands

int pn_scan_command(const std::string& iface, std::ostream& out, std::ostream& err) {
  auto port = open_port(iface, "--pn-scan", err);
  if (!port) return 1;
  const auto stations = dcp_scan(*port, kScanWindow);
  out << format_scan(stations, iface, kScanWindow);
  return 0;
}

int pn_set_name_command(const std::string& iface, const std::string& mac, const std::string& name,
                        std::ostream& out, std::ostream& err) {
  const auto m = parse_mac_arg(mac, "--pn-set-name", err);
  if (!m) return 2;
  if (!valid_station_name(name)) {
    err << "plcrun: --pn-set-name: '" << name
        << "' is not a valid NameOfStation (IEC 61158-6-10: labels of a-z, 0-9 and '-' "
           "separated by '.', each 1..63 characters not starting or ending with '-', 240 in "
           "all, not an IP address, not port-NNN...); nothing sent\n";
    return 2;
  }
  DcpSetRequest req;
  req.station_name = name;
  req.permanent = true;
  return run_set(iface, *m, req, "--pn-set-name", "NameOfStation set to '" + name + "'", out, err);
}

int pn_set_ip_command(const std::string& iface, const std::string& mac, const std::string& ip,
                      std::ostream& out, std::ostream& err) {
  const auto m = parse_mac_arg(mac, "--pn-set-ip", err);
  if (!m) return 2;
  std::string why;
  const auto suite = parse_ip_suite(ip, why);
  if (!suite) {
    err << "plcrun: --pn-set-ip: " << why << " (IP[/PREFIX[/GATEWAY]], e.g. 192.168.0.10/24); "
        << "nothing sent\n";
    return 2;
  }
  DcpSetRequest req;
  req.ip = *suite;
  req.permanent = true;
  return run_set(iface, *m, req, "--pn-set-ip", "IP set to " + ip_text(*suite), out, err);
}

}  // namespace plc::profinet
