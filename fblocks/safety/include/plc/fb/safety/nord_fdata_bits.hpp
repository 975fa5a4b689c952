// Bit map of the NORD SK TU4-PNS / SK CU4-PNS F-data (4 bytes each way),
// spec nord-profisafe.md §2.3 (host -> device, the manual's "F-data In") and
// §2.4 (device -> host, "F-data Out"). Byte 0 is the first byte on the wire.
#pragma once

#include <cstddef>
#include <cstdint>

namespace plc::safety::nord {

inline constexpr std::size_t kFDataBytes = 4;

struct Bit {
  std::uint8_t byte;
  std::uint8_t bit;
};

// Request telegram A, host -> device (§2.3).
namespace in {
inline constexpr Bit kOssd1{0, 0};       // In 0.0 switch SO1 on
inline constexpr Bit kSos{0, 3};         // In 0.3 activate SOS
inline constexpr Bit kSls{0, 4};         // In 0.4 activate SLS
inline constexpr Bit kSlsLevel0{1, 1};   // In 1.1 SLS speed selection bit 0
inline constexpr Bit kSlsLevel1{1, 2};   // In 1.2 SLS speed selection bit 1
inline constexpr Bit kSdiP{1, 4};        // In 1.4 activate SDI-P
inline constexpr Bit kSdiN{1, 5};        // In 1.5 activate SDI-N
inline constexpr Bit kOssd2{3, 0};       // In 3.0 switch SO2 on
inline constexpr Bit kOssd3{3, 1};       // In 3.1 switch SO3 on
inline constexpr Bit kSsr{3, 6};         // In 3.6 activate SSR
inline constexpr Bit kChannelAck{3, 7};  // In 3.7 acknowledge channel passivation
}  // namespace in

// Response telegram B, device -> host (§2.4). OSSD and clock bits are
// inverted: 1 = switched OFF.
namespace out {
inline constexpr Bit kOssd1Off{0, 0};   // Out 0.0
inline constexpr Bit kSosOk{0, 3};      // Out 0.3
inline constexpr Bit kSlsOk{0, 4};      // Out 0.4 (manual's "SOS" typo, spec [AMBIG])
inline constexpr Bit kSlsLevel0{1, 1};  // Out 1.1
inline constexpr Bit kSlsLevel1{1, 2};  // Out 1.2
inline constexpr Bit kSdiPOk{1, 4};     // Out 1.4
inline constexpr Bit kSdiNOk{1, 5};     // Out 1.5
inline constexpr Bit kSsm{1, 7};        // Out 1.7
inline constexpr Bit kOssd2Off{3, 0};   // Out 3.0
inline constexpr Bit kOssd3Off{3, 1};   // Out 3.1
inline constexpr Bit kClock1Off{3, 2};  // Out 3.2
inline constexpr Bit kClock2Off{3, 3};  // Out 3.3
inline constexpr Bit kSi1{3, 4};        // Out 3.4
inline constexpr Bit kSi2{3, 5};        // Out 3.5
inline constexpr Bit kSsrOk{3, 6};      // Out 3.6
}  // namespace out

constexpr bool get(const std::uint8_t* d, Bit b) { return (d[b.byte] >> b.bit) & 1u; }
constexpr void put(std::uint8_t* d, Bit b, bool on) {
  d[b.byte] = on ? static_cast<std::uint8_t>(d[b.byte] | (1u << b.bit))
                 : static_cast<std::uint8_t>(d[b.byte] & ~(1u << b.bit));
}

}  // namespace plc::safety::nord
