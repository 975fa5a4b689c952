// DP-V0 services on FDL (EN 50170 vol. 2, DP; IEC 61158-6-3): SAPs, the
// Set_Prm block, the diagnosis, Global_Control.
//   Data_Exchange  no SAPs (default SAP), SRD: outputs -> inputs
//   Slave_Diag     DSAP 60, SSAP 62, SRD: -> 6 + n diagnosis bytes
//   Set_Prm        DSAP 61, SSAP 62, SRD: 7 + n bytes -> SC
//   Chk_Cfg        DSAP 62, SSAP 62, SRD: Cfg bytes -> SC
//   Get_Cfg        DSAP 59, SSAP 62, SRD: -> Cfg bytes
//   Global_Control DSAP 58, SSAP 62, SDN to 127: Control_Command, Group_Select
// A slave answers a service it cannot give now with RS (no service
// activated), e.g. Data_Exchange before it is parametrised.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace plc::profibus::dp {

inline constexpr std::int16_t kSapMaster = 62;  // the master's SSAP for DP-V0 (MS0)
inline constexpr std::int16_t kSapSetSlaveAdd = 55;
inline constexpr std::int16_t kSapRdInp = 56;
inline constexpr std::int16_t kSapRdOutp = 57;
inline constexpr std::int16_t kSapGlobalControl = 58;
inline constexpr std::int16_t kSapGetCfg = 59;
inline constexpr std::int16_t kSapSlaveDiag = 60;
inline constexpr std::int16_t kSapSetPrm = 61;
inline constexpr std::int16_t kSapChkCfg = 62;

// Set_Prm Station_Status bits.
inline constexpr std::uint8_t kPrmWdOn = 0x08;
inline constexpr std::uint8_t kPrmFreezeReq = 0x10;
inline constexpr std::uint8_t kPrmSyncReq = 0x20;
inline constexpr std::uint8_t kPrmUnlockReq = 0x40;
inline constexpr std::uint8_t kPrmLockReq = 0x80;

struct SetPrm {
  std::uint8_t station_status = kPrmLockReq;
  std::uint8_t wd_fact1 = 1, wd_fact2 = 1;  // watchdog = 10 ms x f1 x f2
  std::uint8_t min_tsdr = 0;                // 0: keep the slave's
  std::uint16_t ident = 0;
  std::uint8_t group = 0;
  std::vector<std::uint8_t> user;

  [[nodiscard]] std::vector<std::uint8_t> encode() const;
  static std::optional<SetPrm> decode(std::span<const std::uint8_t> du);
  // 10 ms x f1 x f2, 0 when WD_On is clear.
  [[nodiscard]] std::uint32_t watchdog_ms() const;
};

// The watchdog factors for a time (rounded up to 10 ms, f1 and f2 in 1..255).
std::pair<std::uint8_t, std::uint8_t> watchdog_factors(std::uint32_t ms);

// Station_Status_1 (diagnosis byte 0).
inline constexpr std::uint8_t kDiag1StationNonExistent = 0x01;  // set by the master
inline constexpr std::uint8_t kDiag1StationNotReady = 0x02;
inline constexpr std::uint8_t kDiag1CfgFault = 0x04;
inline constexpr std::uint8_t kDiag1ExtDiag = 0x08;
inline constexpr std::uint8_t kDiag1NotSupported = 0x10;
inline constexpr std::uint8_t kDiag1InvalidSlaveResponse = 0x20;  // set by the master
inline constexpr std::uint8_t kDiag1PrmFault = 0x40;
inline constexpr std::uint8_t kDiag1MasterLock = 0x80;
// Station_Status_2 (byte 1).
inline constexpr std::uint8_t kDiag2PrmReq = 0x01;
inline constexpr std::uint8_t kDiag2StatDiag = 0x02;
inline constexpr std::uint8_t kDiag2Always1 = 0x04;
inline constexpr std::uint8_t kDiag2WdOn = 0x08;
inline constexpr std::uint8_t kDiag2FreezeMode = 0x10;
inline constexpr std::uint8_t kDiag2SyncMode = 0x20;
inline constexpr std::uint8_t kDiag2Deactivated = 0x80;  // set by the master
// Station_Status_3 (byte 2).
inline constexpr std::uint8_t kDiag3ExtDiagOverflow = 0x80;

struct Diagnosis {
  std::uint8_t status1 = 0, status2 = kDiag2Always1, status3 = 0;
  std::uint8_t master = 0xFF;  // Diag.Master_Add: 255 = not parametrised
  std::uint16_t ident = 0;
  std::vector<std::uint8_t> ext;  // extended diagnosis blocks

  [[nodiscard]] std::vector<std::uint8_t> encode() const;
  static std::optional<Diagnosis> decode(std::span<const std::uint8_t> du);
  // Ready for Data_Exchange: no fault bit, no Prm_Req, not Station_Not_Ready.
  [[nodiscard]] bool ready() const;
  // "Prm_Fault Prm_Req WD_On ...", the names of the bits set (the
  // always-1 bit left out), and the extended diagnosis.
  [[nodiscard]] std::string text() const;
};

// Extended diagnosis blocks (DP §8.3.4.6): header bits 7-6 = 00 device, 01
// identifier, 10 channel; the header's bits 5-0 the block length.
std::string ext_diag_text(std::span<const std::uint8_t> ext);

// Global_Control Control_Command bits.
inline constexpr std::uint8_t kGcClearData = 0x02;
inline constexpr std::uint8_t kGcUnfreeze = 0x04;
inline constexpr std::uint8_t kGcFreeze = 0x08;
inline constexpr std::uint8_t kGcUnsync = 0x10;
inline constexpr std::uint8_t kGcSync = 0x20;

struct GlobalControl {
  std::uint8_t command = 0;
  std::uint8_t group_select = 0;  // 0: every slave
  [[nodiscard]] std::array<std::uint8_t, 2> encode() const { return {command, group_select}; }
  [[nodiscard]] bool addresses(std::uint8_t slave_group) const {
    return group_select == 0 || (group_select & slave_group) != 0;
  }
};

}  // namespace plc::profibus::dp
