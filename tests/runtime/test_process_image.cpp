// Process image: typed big/little-endian access and the bitwise merge that
// lets several tasks share %Q/%M bytes.
#include <gtest/gtest.h>

#include <vector>

#include "plc/io/byte_order.hpp"
#include "plc/io/located.hpp"
#include "plc/io/process_image.hpp"

using namespace plc::io;

TEST(ByteOrder, BigAndLittleEndianLayouts) {
  std::vector<std::uint8_t> b(16, 0);
  store_be<std::uint16_t>(b, 0, 0x047F);
  EXPECT_EQ(b[0], 0x04);
  EXPECT_EQ(b[1], 0x7F);
  store_le<std::uint16_t>(b, 2, 0x047F);
  EXPECT_EQ(b[2], 0x7F);
  EXPECT_EQ(b[3], 0x04);
  store_be<std::int32_t>(b, 4, -2);
  EXPECT_EQ(b[4], 0xFF);
  EXPECT_EQ(b[7], 0xFE);
  EXPECT_EQ(load_be<std::int32_t>(b, 4), -2);
  store_be<float>(b, 8, 1.0F);  // IEEE 754 0x3F800000
  EXPECT_EQ(b[8], 0x3F);
  EXPECT_EQ(b[9], 0x80);
  EXPECT_FLOAT_EQ(load_be<float>(b, 8), 1.0F);
  store_le<double>(b, 8, -0.5);
  EXPECT_DOUBLE_EQ(load_le<double>(b, 8), -0.5);
}

TEST(ProcessImage, MergeTakesOnlyTheBitsTheTaskChanged) {
  // Global byte 0b1010'0000 written by another task; this task saw
  // 0b0000'0000 at scan start and set bit 0.
  std::vector<std::uint8_t> global(20, 0), before(20, 0), after(20, 0);
  global[0] = 0xA0;
  after[0] = 0x01;
  global[13] = 0xF0;
  before[13] = 0x0F;
  after[13] = 0x0E;  // this task cleared bit 0 of byte 13
  merge_changes(global, before, after);
  EXPECT_EQ(global[0], 0xA1);
  EXPECT_EQ(global[13], 0xF0);  // bit 0 was already 0 globally; others kept
  before[5] = 0xFF;
  after[5] = 0xFF;
  global[5] = 0x00;
  merge_changes(global, before, after);
  EXPECT_EQ(global[5], 0x00) << "unchanged bytes keep the global value";
}

TEST(Located, ReadsAndWritesTheImageInItsByteOrder) {
  ProcessImage img({16, 16, 16});
  Located<plc::INT> w{"%QW2"};
  Located<plc::BOOL> x{"%QX1.3"};
  Located<plc::REAL> r{"%QD4"};
  Located<plc::WORD> sw{"%QW8"};
  w.bind(img.area(Area::Output).data() + 2, 0, ByteOrder::Big);
  x.bind(img.area(Area::Output).data() + 1, 3, ByteOrder::Big);
  r.bind(img.area(Area::Output).data() + 4, 0, ByteOrder::Little);
  sw.bind(img.area(Area::Output).data() + 8, 0, ByteOrder::Big);
  w = plc::INT(0x1234);
  x = true;
  r = 1.0F;
  sw = 0x047F;
  auto q = img.area(Area::Output);
  EXPECT_EQ(q[2], 0x12);
  EXPECT_EQ(q[3], 0x34);
  EXPECT_EQ(q[1], 0x08);
  EXPECT_EQ(q[7], 0x3F);  // little-endian float: high byte last
  EXPECT_EQ(q[8], 0x04);
  EXPECT_TRUE(sw.get().bit(0));
  x = false;
  EXPECT_EQ(q[1], 0x00);
  EXPECT_EQ(w.get(), 0x1234);
}

TEST(Located, UnboundVariablesUseScratchStorage) {
  Located<plc::DINT> v{"%ID0"};
  EXPECT_FALSE(v.bound());
  v = 42;
  EXPECT_EQ(v.get(), 42);
}

// Issue 10 point 8: `image: {memory: 0}` is a valid config. An empty area's
// data() may be null, which copy_from passed to memcpy (undefined behaviour;
// UBSan: "null pointer passed as argument").
TEST(ProcessImage, CopiesImagesWithEmptyAreas) {
  ProcessImage a, b;
  a.resize({4, 0, 0});
  b.resize({4, 0, 0});
  a.area(Area::Input)[3] = 0x5A;
  b.copy_from(a);
  EXPECT_EQ(b.area(Area::Input)[3], 0x5A);
  ProcessImage empty_a, empty_b;
  empty_a.resize({0, 0, 0});
  empty_b.resize({0, 0, 0});
  empty_b.copy_from(empty_a);
  EXPECT_TRUE(empty_b.area(Area::Memory).empty());
}
