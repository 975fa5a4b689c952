// PROFIdrive telegrams 3, 9 and 111 of the HIWIN E1 (spec §3.1 Table 3.2.1
// for the sizes, §3.2 Table 3.2.2 for the word order). Big-endian on the
// wire; a 32-bit signal puts its high word in the lower-numbered PZD [STD].
// Reserved PZDs (telegram 111 PZD12) are sent as 0 and ignored on receive.
//
// "Out" = PLC -> drive (the drive's received words), "In" = drive -> PLC.
// The k...Offset constants are the byte offsets of Table 3.2.2.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "plc/fb/drive/profidrive_words.hpp"
#include "plc/io/byte_order.hpp"

namespace plc::drive {

enum class TelegramType : std::uint16_t { Standard3 = 3, Standard9 = 9, Hiwin111 = 111 };

constexpr bool is_positioning(TelegramType t) { return t != TelegramType::Standard3; }
constexpr bool is_supported_telegram(unsigned n) { return n == 3 || n == 9 || n == 111; }

namespace wire {
inline std::uint16_t u16(std::span<const std::uint8_t> b, std::size_t off) {
  return io::load_be<std::uint16_t>(b, off);
}
inline std::int16_t i16(std::span<const std::uint8_t> b, std::size_t off) {
  return io::load_be<std::int16_t>(b, off);
}
inline std::int32_t i32(std::span<const std::uint8_t> b, std::size_t off) {
  return io::load_be<std::int32_t>(b, off);
}
inline std::uint32_t u32(std::span<const std::uint8_t> b, std::size_t off) {
  return io::load_be<std::uint32_t>(b, off);
}
inline void put16(std::span<std::uint8_t> b, std::size_t off, std::uint16_t v) {
  io::store_be<std::uint16_t>(b, off, v);
}
inline void put32(std::span<std::uint8_t> b, std::size_t off, std::uint32_t v) {
  io::store_be<std::uint32_t>(b, off, v);
}
}  // namespace wire

// ---------------------------------------------------------------- telegram 3
// Speed mode with encoder 1: 5 words PLC -> drive, 9 words drive -> PLC.
struct Telegram3Out {
  static constexpr std::size_t kWords = 5, kBytes = 10;
  static constexpr std::size_t kStw1 = 0, kNsollB = 2, kStw2 = 6, kG1Stw = 8;
  Stw1Speed stw1;
  std::int32_t nsoll_b{};  // 0x40000000 = 100 % of Pt317 (spec §2, §7.1)
  Stw2 stw2;
  G1Stw g1_stw;

  void encode(std::span<std::uint8_t> b) const {
    wire::put16(b, kStw1, stw1.word());
    wire::put32(b, kNsollB, static_cast<std::uint32_t>(nsoll_b));
    wire::put16(b, kStw2, stw2.word());
    wire::put16(b, kG1Stw, g1_stw.word());
  }
  static Telegram3Out decode(std::span<const std::uint8_t> b) {
    Telegram3Out t;
    t.stw1 = Stw1Speed::from(wire::u16(b, kStw1));
    t.nsoll_b = wire::i32(b, kNsollB);
    t.stw2 = Stw2::from(wire::u16(b, kStw2));
    t.g1_stw = G1Stw::from(wire::u16(b, kG1Stw));
    return t;
  }
};

struct Telegram3In {
  static constexpr std::size_t kWords = 9, kBytes = 18;
  static constexpr std::size_t kZsw1 = 0, kNistB = 2, kZsw2 = 6, kG1Zsw = 8, kG1Xist1 = 10,
                               kG1Xist2 = 14;
  Zsw1Speed zsw1;
  std::int32_t nist_b{};
  Zsw2 zsw2;
  G1Zsw g1_zsw;
  // Typed Uint32 in Table 3.1.1 but with a signed range (spec §10.3.3): kept
  // unsigned here, as PROFIdrive wraps it as an unsigned 32-bit counter.
  std::uint32_t g1_xist1{};
  std::uint32_t g1_xist2{};

  void encode(std::span<std::uint8_t> b) const {
    wire::put16(b, kZsw1, zsw1.word());
    wire::put32(b, kNistB, static_cast<std::uint32_t>(nist_b));
    wire::put16(b, kZsw2, zsw2.word(false));
    wire::put16(b, kG1Zsw, g1_zsw.word());
    wire::put32(b, kG1Xist1, g1_xist1);
    wire::put32(b, kG1Xist2, g1_xist2);
  }
  static Telegram3In decode(std::span<const std::uint8_t> b) {
    Telegram3In t;
    t.zsw1 = Zsw1Speed::from(wire::u16(b, kZsw1));
    t.nist_b = wire::i32(b, kNistB);
    t.zsw2 = Zsw2::from(wire::u16(b, kZsw2), false);
    t.g1_zsw = G1Zsw::from(wire::u16(b, kG1Zsw));
    t.g1_xist1 = wire::u32(b, kG1Xist1);
    t.g1_xist2 = wire::u32(b, kG1Xist2);
    return t;
  }
};

// ---------------------------------------------------------------- telegram 9
// Position mode, MDI via SATZANW: 10 words PLC -> drive, 5 words drive -> PLC.
struct Telegram9Out {
  static constexpr std::size_t kWords = 10, kBytes = 20;
  static constexpr std::size_t kStw1 = 0, kSatzanw = 2, kStw2 = 4, kMdiTarpos = 6,
                               kMdiVelocity = 10, kMdiAcc = 14, kMdiDec = 16, kMdiMode = 18;
  Stw1Pos stw1;
  Satzanw satzanw;
  Stw2 stw2;
  std::int32_t mdi_tarpos{};    // 1 = 1 CU
  std::int32_t mdi_velocity{};  // 1 = 1000 CU/min, 0..2^31-1
  std::int16_t mdi_acc{};       // 0x4000 = 100 % of Pt534
  std::int16_t mdi_dec{};       // 0x4000 = 100 % of Pt537
  MdiMode mdi_mode;

  void encode(std::span<std::uint8_t> b) const {
    wire::put16(b, kStw1, stw1.word());
    wire::put16(b, kSatzanw, satzanw.word());
    wire::put16(b, kStw2, stw2.word());
    wire::put32(b, kMdiTarpos, static_cast<std::uint32_t>(mdi_tarpos));
    wire::put32(b, kMdiVelocity, static_cast<std::uint32_t>(mdi_velocity));
    wire::put16(b, kMdiAcc, static_cast<std::uint16_t>(mdi_acc));
    wire::put16(b, kMdiDec, static_cast<std::uint16_t>(mdi_dec));
    wire::put16(b, kMdiMode, mdi_mode.word());
  }
  static Telegram9Out decode(std::span<const std::uint8_t> b) {
    Telegram9Out t;
    t.stw1 = Stw1Pos::from(wire::u16(b, kStw1));
    t.satzanw = Satzanw::from(wire::u16(b, kSatzanw));
    t.stw2 = Stw2::from(wire::u16(b, kStw2));
    t.mdi_tarpos = wire::i32(b, kMdiTarpos);
    t.mdi_velocity = wire::i32(b, kMdiVelocity);
    t.mdi_acc = wire::i16(b, kMdiAcc);
    t.mdi_dec = wire::i16(b, kMdiDec);
    t.mdi_mode = MdiMode::from(wire::u16(b, kMdiMode));
    return t;
  }
};

struct Telegram9In {
  static constexpr std::size_t kWords = 5, kBytes = 10;
  static constexpr std::size_t kZsw1 = 0, kAktsatz = 2, kZsw2 = 4, kXistA = 6;
  Zsw1Pos zsw1;
  Aktsatz aktsatz;
  Zsw2 zsw2;
  std::int32_t xist_a{};

  void encode(std::span<std::uint8_t> b) const {
    wire::put16(b, kZsw1, zsw1.word());
    wire::put16(b, kAktsatz, aktsatz.word());
    wire::put16(b, kZsw2, zsw2.word());
    wire::put32(b, kXistA, static_cast<std::uint32_t>(xist_a));
  }
  static Telegram9In decode(std::span<const std::uint8_t> b) {
    Telegram9In t;
    t.zsw1 = Zsw1Pos::from(wire::u16(b, kZsw1));
    t.aktsatz = Aktsatz::from(wire::u16(b, kAktsatz));
    t.zsw2 = Zsw2::from(wire::u16(b, kZsw2));
    t.xist_a = wire::i32(b, kXistA);
    return t;
  }
};

// -------------------------------------------------------------- telegram 111
// Position mode, MDI via POS_STW1: 12 words each way; PZD12 reserved.
struct Telegram111Out {
  static constexpr std::size_t kWords = 12, kBytes = 24;
  static constexpr std::size_t kStw1 = 0, kPosStw1 = 2, kPosStw2 = 4, kStw2 = 6, kOverride = 8,
                               kMdiTarpos = 10, kMdiVelocity = 14, kMdiAcc = 18, kMdiDec = 20,
                               kReserved12 = 22;
  Stw1Pos stw1;
  PosStw1 pos_stw1;
  PosStw2 pos_stw2;
  Stw2 stw2;
  std::uint16_t override_{0x4000};  // 0x4000 = 100 % of MDI velocity, 0..32767
  std::int32_t mdi_tarpos{};
  std::int32_t mdi_velocity{};
  std::int16_t mdi_acc{};
  std::int16_t mdi_dec{};

  void encode(std::span<std::uint8_t> b) const {
    wire::put16(b, kStw1, stw1.word());
    wire::put16(b, kPosStw1, pos_stw1.word());
    wire::put16(b, kPosStw2, pos_stw2.word());
    wire::put16(b, kStw2, stw2.word());
    wire::put16(b, kOverride, override_);
    wire::put32(b, kMdiTarpos, static_cast<std::uint32_t>(mdi_tarpos));
    wire::put32(b, kMdiVelocity, static_cast<std::uint32_t>(mdi_velocity));
    wire::put16(b, kMdiAcc, static_cast<std::uint16_t>(mdi_acc));
    wire::put16(b, kMdiDec, static_cast<std::uint16_t>(mdi_dec));
    wire::put16(b, kReserved12, 0);
  }
  static Telegram111Out decode(std::span<const std::uint8_t> b) {
    Telegram111Out t;
    t.stw1 = Stw1Pos::from(wire::u16(b, kStw1));
    t.pos_stw1 = PosStw1::from(wire::u16(b, kPosStw1));
    t.pos_stw2 = PosStw2::from(wire::u16(b, kPosStw2));
    t.stw2 = Stw2::from(wire::u16(b, kStw2));
    t.override_ = wire::u16(b, kOverride);
    t.mdi_tarpos = wire::i32(b, kMdiTarpos);
    t.mdi_velocity = wire::i32(b, kMdiVelocity);
    t.mdi_acc = wire::i16(b, kMdiAcc);
    t.mdi_dec = wire::i16(b, kMdiDec);
    return t;
  }
};

struct Telegram111In {
  static constexpr std::size_t kWords = 12, kBytes = 24;
  static constexpr std::size_t kZsw1 = 0, kPosZsw1 = 2, kPosZsw2 = 4, kZsw2 = 6, kMeldw = 8,
                               kXistA = 10, kNistB = 14, kFaultCode = 18, kWarnCode = 20,
                               kReserved12 = 22;
  Zsw1Pos zsw1;
  PosZsw1 pos_zsw1;
  PosZsw2 pos_zsw2;
  Zsw2 zsw2;
  Meldw meldw;
  std::int32_t xist_a{};
  std::int32_t nist_b{};
  std::uint16_t fault_code{};
  std::uint16_t warn_code{};

  void encode(std::span<std::uint8_t> b) const {
    wire::put16(b, kZsw1, zsw1.word());
    wire::put16(b, kPosZsw1, pos_zsw1.word());
    wire::put16(b, kPosZsw2, pos_zsw2.word());
    wire::put16(b, kZsw2, zsw2.word());
    wire::put16(b, kMeldw, meldw.word());
    wire::put32(b, kXistA, static_cast<std::uint32_t>(xist_a));
    wire::put32(b, kNistB, static_cast<std::uint32_t>(nist_b));
    wire::put16(b, kFaultCode, fault_code);
    wire::put16(b, kWarnCode, warn_code);
    wire::put16(b, kReserved12, 0);
  }
  static Telegram111In decode(std::span<const std::uint8_t> b) {
    Telegram111In t;
    t.zsw1 = Zsw1Pos::from(wire::u16(b, kZsw1));
    t.pos_zsw1 = PosZsw1::from(wire::u16(b, kPosZsw1));
    t.pos_zsw2 = PosZsw2::from(wire::u16(b, kPosZsw2));
    t.zsw2 = Zsw2::from(wire::u16(b, kZsw2));
    t.meldw = Meldw::from(wire::u16(b, kMeldw));
    t.xist_a = wire::i32(b, kXistA);
    t.nist_b = wire::i32(b, kNistB);
    t.fault_code = wire::u16(b, kFaultCode);
    t.warn_code = wire::u16(b, kWarnCode);
    return t;
  }
};

// Sizes of a telegram in bytes, PLC -> drive and drive -> PLC (Table 3.2.1).
constexpr std::size_t out_bytes(TelegramType t) {
  switch (t) {
    case TelegramType::Standard3:
      return Telegram3Out::kBytes;
    case TelegramType::Standard9:
      return Telegram9Out::kBytes;
    case TelegramType::Hiwin111:
      return Telegram111Out::kBytes;
  }
  return 0;
}
constexpr std::size_t in_bytes(TelegramType t) {
  switch (t) {
    case TelegramType::Standard3:
      return Telegram3In::kBytes;
    case TelegramType::Standard9:
      return Telegram9In::kBytes;
    case TelegramType::Hiwin111:
      return Telegram111In::kBytes;
  }
  return 0;
}

}  // namespace plc::drive
