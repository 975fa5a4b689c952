#include "plc/profibus/dp/describe.hpp"

#include <cstdio>

#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/dp/services.hpp"

namespace plc::profibus::dp {

namespace {

const char* request_name(std::uint8_t f) {
  switch (f) {
    case fdl::kReqTimeEvent:
      return "TE";
    case fdl::kReqSdaLow:
      return "SDA_low";
    case fdl::kReqSdnLow:
      return "SDN_low";
    case fdl::kReqSdaHigh:
      return "SDA_high";
    case fdl::kReqSdnHigh:
      return "SDN_high";
    case fdl::kReqDdb:
      return "DDB";
    case fdl::kReqFdlStatus:
      return "FDL_Status";
    case fdl::kReqSrdLow:
      return "SRD_low";
    case fdl::kReqSrdHigh:
      return "SRD_high";
    case fdl::kReqIdent:
      return "Ident";
    case fdl::kReqLsapStatus:
      return "LSAP_Status";
    default:
      return "request?";
  }
}

const char* response_name(std::uint8_t f) {
  switch (f) {
    case fdl::kResOk:
      return "OK";
    case fdl::kResUserError:
      return "UE";
    case fdl::kResNoResource:
      return "RR";
    case fdl::kResNoService:
      return "RS";
    case fdl::kResDataLow:
      return "DL";
    case fdl::kResNoData:
      return "NR";
    case fdl::kResDataHigh:
      return "DH";
    case fdl::kResDataLowNoRes:
      return "RDL";
    case fdl::kResDataHighNoRes:
      return "RDH";
    default:
      return "response?";
  }
}

const char* service(const fdl::Telegram& t) {
  const std::int16_t sap = t.request() ? t.dsap : t.ssap;
  if (t.dsap < 0 && t.ssap < 0) {
    // Data_Exchange: an SRD without SAPs, answered DL/DH (or RS when
    // refused); an FDL status request and its OK answer are no DP service.
    if (t.request())
      return (t.function() == fdl::kReqSrdHigh || t.function() == fdl::kReqSrdLow) ? "Data_Exchange"
                                                                                   : "";
    const std::uint8_t f = t.function();
    return (f == fdl::kResDataLow || f == fdl::kResDataHigh || f == fdl::kResDataLowNoRes ||
            f == fdl::kResDataHighNoRes)
               ? "Data_Exchange"
               : "";
  }
  switch (sap) {
    case kSapSetSlaveAdd:
      return "Set_Slave_Add";
    case kSapRdInp:
      return "Rd_Inp";
    case kSapRdOutp:
      return "Rd_Outp";
    case kSapGlobalControl:
      return "Global_Control";
    case kSapGetCfg:
      return "Get_Cfg";
    case kSapSlaveDiag:
      return "Slave_Diag";
    case kSapSetPrm:
      return "Set_Prm";
    case kSapChkCfg:
      return t.request() ? "Chk_Cfg" : "?";
    default:
      return "SAP?";
  }
}

}  // namespace

std::string describe(const fdl::Telegram& t) {
  char b[160];
  if (t.format == fdl::Format::ShortAck) return "SC";
  if (t.format == fdl::Format::Token) {
    std::snprintf(b, sizeof b, "SD4 token %u->%u", t.sa, t.da);
    return b;
  }
  std::string s;
  if (t.request()) {
    std::snprintf(b, sizeof b, "%s %u->%u %s%s", fdl::to_string(t.format), t.sa, t.da,
                  request_name(t.function()),
                  (t.fc & fdl::kFcFcv) ? ((t.fc & fdl::kFcFcb) ? " FCB=1" : " FCB=0") : "");
  } else {
    static const char* const kType[4] = {"slave", "master not ready", "master ready",
                                         "master in ring"};
    std::snprintf(b, sizeof b, "%s %u->%u %s (%s)", fdl::to_string(t.format), t.sa, t.da,
                  response_name(t.function()), kType[(t.fc >> 4) & 3]);
  }
  s = b;
  if (t.dsap >= 0 || t.ssap >= 0) {
    std::snprintf(b, sizeof b, " DSAP %d SSAP %d", t.dsap, t.ssap);
    s += b;
  }
  const char* svc = service(t);
  if (*svc) s += std::string(" ") + svc;
  const auto du = t.du();
  if (t.request() && t.dsap == kSapSetPrm) {
    if (const auto p = SetPrm::decode(du)) {
      std::snprintf(b, sizeof b, ": status 0x%02X WD %u ms minTSDR %u ident 0x%04X group 0x%02X",
                    p->station_status, p->watchdog_ms(), p->min_tsdr, p->ident, p->group);
      s += b;
      if (!p->user.empty()) s += " user " + hex(p->user);
      return s;
    }
  }
  if (!t.request() && t.ssap == kSapSlaveDiag) {
    if (const auto d = Diagnosis::decode(du)) return s + ": " + d->text();
  }
  if (t.request() && t.dsap == kSapGlobalControl && du.size() == 2) {
    std::string c;
    if (du[0] & kGcClearData) c += " Clear_Data";
    if (du[0] & kGcUnfreeze) c += " Unfreeze";
    if (du[0] & kGcFreeze) c += " Freeze";
    if (du[0] & kGcUnsync) c += " Unsync";
    if (du[0] & kGcSync) c += " Sync";
    std::snprintf(b, sizeof b, ":%s group 0x%02X", c.empty() ? " (none)" : c.c_str(), du[1]);
    return s + b;
  }
  if (!du.empty()) s += ": " + hex(du);
  return s;
}

}  // namespace plc::profibus::dp
