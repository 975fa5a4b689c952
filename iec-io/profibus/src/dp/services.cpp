#include "plc/profibus/dp/services.hpp"

#include <algorithm>
#include <cstdio>

namespace plc::profibus::dp {

std::vector<std::uint8_t> SetPrm::encode() const {
  // Byte by byte (an initializer list + insert trips GCC 12's -Warray-bounds).
  std::vector<std::uint8_t> b(7 + user.size());
  b[0] = station_status;
  b[1] = wd_fact1;
  b[2] = wd_fact2;
  b[3] = min_tsdr;
  b[4] = static_cast<std::uint8_t>(ident >> 8);
  b[5] = static_cast<std::uint8_t>(ident);
  b[6] = group;
  std::copy(user.begin(), user.end(), b.begin() + 7);
  return b;
}

std::optional<SetPrm> SetPrm::decode(std::span<const std::uint8_t> du) {
  if (du.size() < 7) return std::nullopt;
  SetPrm p;
  p.station_status = du[0];
  p.wd_fact1 = du[1];
  p.wd_fact2 = du[2];
  p.min_tsdr = du[3];
  p.ident = static_cast<std::uint16_t>(du[4] << 8 | du[5]);
  p.group = du[6];
  p.user.assign(du.begin() + 7, du.end());
  return p;
}

std::uint32_t SetPrm::watchdog_ms() const {
  return (station_status & kPrmWdOn) ? 10u * wd_fact1 * wd_fact2 : 0u;
}

std::pair<std::uint8_t, std::uint8_t> watchdog_factors(std::uint32_t ms) {
  const std::uint32_t units = std::clamp<std::uint32_t>((ms + 9) / 10, 1, 255 * 255);
  // The smallest f2 for which f1 fits in a byte, then f1 rounded up.
  const std::uint32_t f2 = (units + 254) / 255;
  const std::uint32_t f1 = (units + f2 - 1) / f2;
  return {static_cast<std::uint8_t>(f1), static_cast<std::uint8_t>(f2)};
}

std::vector<std::uint8_t> Diagnosis::encode() const {
  std::vector<std::uint8_t> b(6 + ext.size());
  b[0] = status1;
  b[1] = status2;
  b[2] = status3;
  b[3] = master;
  b[4] = static_cast<std::uint8_t>(ident >> 8);
  b[5] = static_cast<std::uint8_t>(ident);
  std::copy(ext.begin(), ext.end(), b.begin() + 6);
  return b;
}

std::optional<Diagnosis> Diagnosis::decode(std::span<const std::uint8_t> du) {
  if (du.size() < 6) return std::nullopt;
  Diagnosis d;
  d.status1 = du[0];
  d.status2 = du[1];
  d.status3 = du[2];
  d.master = du[3];
  d.ident = static_cast<std::uint16_t>(du[4] << 8 | du[5]);
  d.ext.assign(du.begin() + 6, du.end());
  return d;
}

bool Diagnosis::ready() const {
  return (status1 & (kDiag1StationNonExistent | kDiag1StationNotReady | kDiag1CfgFault |
                     kDiag1PrmFault | kDiag1InvalidSlaveResponse | kDiag1NotSupported)) == 0 &&
         (status2 & (kDiag2PrmReq | kDiag2StatDiag)) == 0;
}

std::string Diagnosis::text() const {
  static const char* const k1[8] = {
      "Station_Non_Existent", "Station_Not_Ready",      "Cfg_Fault", "Ext_Diag",
      "Not_Supported",        "Invalid_Slave_Response", "Prm_Fault", "Master_Lock"};
  static const char* const k2[8] = {"Prm_Req",     "Stat_Diag", nullptr,    "WD_On",
                                    "Freeze_Mode", "Sync_Mode", "reserved", "Deactivated"};
  std::string s;
  auto add = [&](const char* n) {
    if (!s.empty()) s += ' ';
    s += n;
  };
  for (int i = 0; i < 8; ++i)
    if (status1 & (1u << i)) add(k1[i]);
  for (int i = 0; i < 8; ++i)
    if ((status2 & (1u << i)) && k2[i]) add(k2[i]);
  if (!(status2 & kDiag2Always1)) add("(Station_Status_2 bit 2 clear)");
  if (status3 & kDiag3ExtDiagOverflow) add("Ext_Diag_Overflow");
  char b[48];
  std::snprintf(b, sizeof b, "master %u ident 0x%04X", master, ident);
  add(b);
  if (!ext.empty()) add(ext_diag_text(ext).c_str());
  return s;
}

std::string ext_diag_text(std::span<const std::uint8_t> ext) {
  std::string s;
  std::size_t i = 0;
  char b[64];
  while (i < ext.size()) {
    const std::uint8_t h = ext[i];
    if (!s.empty()) s += "; ";
    switch (h >> 6) {
      case 0:
      case 1: {
        const std::size_t len = h & 0x3F;
        if (len < 1 || i + len > ext.size()) return s + "ext diag cut off";
        if (h >> 6 == 1) {
          s += "identifier diag: modules";
          for (std::size_t k = 1; k < len; ++k)
            for (int bit = 0; bit < 8; ++bit)
              if (ext[i + k] & (1u << bit)) {
                std::snprintf(b, sizeof b, " %zu", (k - 1) * 8 + static_cast<std::size_t>(bit));
                s += b;
              }
        } else {
          s += "device diag:";
          for (std::size_t k = 1; k < len; ++k) {
            std::snprintf(b, sizeof b, " %02X", ext[i + k]);
            s += b;
          }
        }
        i += len;
        break;
      }
      case 2: {
        if (i + 3 > ext.size()) return s + "ext diag cut off";
        std::snprintf(b, sizeof b, "channel diag: module %u channel %u%s%s error %u", h & 0x3F,
                      ext[i + 1] & 0x3F, (ext[i + 1] & 0x40) ? " in" : "",
                      (ext[i + 1] & 0x80) ? " out" : "", ext[i + 2] & 0x1F);
        s += b;
        i += 3;
        break;
      }
      default:
        return s + "reserved ext diag block";
    }
  }
  return s;
}

}  // namespace plc::profibus::dp
