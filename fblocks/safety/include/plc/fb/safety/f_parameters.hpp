// The 14-byte PROFIsafe F-parameter block (spec nord-profisafe.md §2.2).
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED SAFETY SOFTWARE.
//
// Layout (bytes big-endian, bit positions are the spec's [SPEC] standard
// positions, to be verified against IEC 61784-3-3 and the NORD GSDML):
//   0      F_Prm_Flag1: bit0 F_Check_SeqNr, bit1 F_Check_iPar, bits2-3 F_SIL,
//                       bits4-5 F_CRC_Length, bits6-7 reserved (0)
//   1      F_Prm_Flag2: bits0-2 reserved (0), bits3-5 F_Block_ID,
//                       bits6-7 F_Par_Version
//   2-3    F_Source_Add   4-5 F_Dest_Add   6-7 F_WD_Time (ms)
//   8-11   F_iPar_CRC     12-13 F_Par_CRC (CRC1 over bytes 0-11)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace plc::safety {

inline constexpr std::size_t kFParamBlockSize = 14;

// Record index of the F-parameter record. The manual gives none (spec §2.2:
// "comes from the GSDML"). [INF] 128 is our choice for the simulation; the
// sim device model uses the same constant.
inline constexpr std::uint16_t kFParamRecordIndex = 128;
// Record the simulated device answers with its current and previous 57xx
// code and its code count (P841, P842, number of codes raised since power-on;
// three big-endian UINTs). [INF] The manual says every code is sent to the
// F-host but not how (spec §5.5, §8.5 item 14); simulation only.
inline constexpr std::uint16_t kNordDiagRecordIndex = 129;

// F_SIL codes (2 bits). 00 = SIL1, 01 = SIL2, 10 = SIL3, 11 = NoSIL [SPEC].
enum class FSil : std::uint8_t { Sil1 = 0, Sil2 = 1, Sil3 = 2, NoSil = 3 };
// The SIL level a code stands for (NoSIL = 0).
constexpr int sil_level(std::uint8_t code) { return code == 3 ? 0 : code + 1; }

struct FParameters {
  bool check_seq_nr = false;       // F_Check_SeqNr: NoCheck on PROFINET [SPEC]
  bool check_ipar = false;         // F_Check_iPar: NORD fixed NoCheck
  std::uint8_t sil = 2;            // F_SIL code, default 10b = SIL3
  std::uint8_t crc_length = 0;     // F_CRC_Length: NORD fixed 00 = 3-byte (10 = 4-byte [SPEC])
  std::uint8_t block_id = 1;       // F_Block_ID: NORD fixed 1 (F_iPar_CRC present)
  std::uint8_t par_version = 1;    // F_Par_Version: NORD fixed 01 = V2 mode
  std::uint16_t source_add = 1;    // F_Source_Add 1..65534
  std::uint16_t dest_add = 1;      // F_Dest_Add 1..65534 (NORD: 1..255)
  std::uint16_t wd_time_ms = 100;  // F_WD_Time 1..10000 ms
  std::uint32_t ipar_crc = 0;      // F_iPar_CRC (NORD P840)
  std::uint16_t par_crc = 0;       // F_Par_CRC (CRC1); filled by encode()
};

// Writes the block. With `fill_crc1` the F_Par_CRC field is computed over
// bytes 0-11 (and stored back into p.par_crc); otherwise p.par_crc is written
// as given (to build deliberately wrong blocks in tests).
void encode(FParameters& p, std::span<std::uint8_t, kFParamBlockSize> out, bool fill_crc1 = true);

// Reads the block back (no checks; the device checks).
FParameters decode(std::span<const std::uint8_t, kFParamBlockSize> in);

// CRC1 over bytes 0-11 of an encoded block.
std::uint16_t compute_crc1(std::span<const std::uint8_t, kFParamBlockSize> block);

}  // namespace plc::safety
