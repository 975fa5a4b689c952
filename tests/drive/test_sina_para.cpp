// SinaPara (parameter access) against the simulated E1: reads, writes, array
// elements, every error class surfaced as ErrorID, record index handling.
#include <gtest/gtest.h>

#include <limits>

#include "drive_test_util.hpp"
#include "plc/fb/drive/mc_blocks.hpp"
#include "plc/fb/drive/sina_para.hpp"

namespace plc::drive::test {

struct SinaParaTest : ::testing::Test {
  Bench b;
  SinaPara fb;
  MC_Power power;
  void body() {
    power(b.ctx, b.axis);
    fb(b.ctx, b.axis);
  }
  void run(int n) {
    b.run([&] { body(); }, n);
  }
  // One job: Start edge, wait for Done or Error, Start low.
  void job() {
    fb.Start = false;
    run(1);
    fb.Start = true;
    ASSERT_TRUE(b.run_until([&] { body(); }, [&] { return fb.Done || fb.Error; }, 100));
    fb.Start = false;
  }
  void read(UINT pnu, UINT sub = 0, UINT count = 0) {
    fb.ReadWrite = false;
    fb.Pnu = pnu;
    fb.Subindex = sub;
    fb.Count = count;
    job();
  }
  void write(UINT pnu, USINT format, LREAL v, UINT sub = 0) {
    fb.ReadWrite = true;
    fb.Pnu = pnu;
    fb.Subindex = sub;
    fb.Count = 0;
    fb.Format = format;
    fb.Value = v;
    job();
  }
};

TEST_F(SinaParaTest, ReadWriteValuesAndArrays) {
  read(pt_pnu(0x317));
  ASSERT_TRUE(fb.Done) << fb.ErrorID.value;
  EXPECT_EQ(fb.ValueRead, 3000);
  EXPECT_EQ(fb.RespFormat, 0x06);
  write(pt_pnu(0x534), 0x06, 250);
  ASSERT_TRUE(fb.Done);
  read(pt_pnu(0x534));
  EXPECT_EQ(fb.ValueRead, 250);
  read(964, 0, 7);  // drive identification, Array[7]
  ASSERT_TRUE(fb.Done);
  EXPECT_EQ(fb.RespCount, 7);
  EXPECT_EQ(fb.ValuesRead[0], 0x0AAA);
  EXPECT_EQ(fb.ValuesRead[2], 208);
  EXPECT_EQ(fb.ValuesRead[6], 16);
  write(0x3201, 0x04, -123456);  // general object i1, Int32
  ASSERT_TRUE(fb.Done);
  read(0x3201);
  EXPECT_EQ(fb.ValueRead, -123456);
  write(0x3212, 0x08, 0.25);  // f2, Float32
  read(0x3212);
  EXPECT_DOUBLE_EQ(fb.ValueRead, 0.25);
  read(ut_pnu(0x004));  // monitor: multi-turn count
  ASSERT_TRUE(fb.Done);
  EXPECT_EQ(fb.ValueRead, 0);
  // Array elements write: fault buffer counter cannot, but 964 is read-only;
  // PNU 950 read 2 elements.
  read(950, 0, 2);
  EXPECT_EQ(fb.ValuesRead[0], 8);
  EXPECT_EQ(fb.ValuesRead[1], 8);
}

// Table 4.3.5.1: a write value must fit the format it is sent in. One that
// does not (out of the type's range, NaN, infinite) is refused with 16#8206
// and not sent; before, 65786 as Uint16 went out as 250 and was accepted,
// and -1 as Uint16 as 65535.
TEST_F(SinaParaTest, Table4_3_5_1_WriteValueOutsideFormatIsRefusedNotWrapped) {
  read(pt_pnu(0x534));
  ASSERT_TRUE(fb.Done);
  const LREAL before = fb.ValueRead;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double v : {65536.0 + 250.0, -1.0, 1e10, nan, inf}) {
    write(pt_pnu(0x534), 0x06, v);
    EXPECT_TRUE(fb.Error) << v;
    EXPECT_EQ(fb.ErrorID, kErrParamValue) << v;
    EXPECT_FALSE(fb.Done) << v;
  }
  for (double v : {3e9, -2147483649.0, nan}) {
    write(0x3201, 0x04, v);  // general object i1, Int32
    EXPECT_EQ(fb.ErrorID, kErrParamValue) << v;
  }
  write(0x3212, 0x08, 1e39);  // f2, Float32: beyond FLT_MAX
  EXPECT_EQ(fb.ErrorID, kErrParamValue);
  write(0x3212, 0x08, inf);
  EXPECT_EQ(fb.ErrorID, kErrParamValue);
  // Array write: one bad element refuses the whole request.
  fb.ReadWrite = true;
  fb.Pnu = 0x3201;
  fb.Count = 2;
  fb.Format = 0x04;
  fb.Value = 1;
  fb.Values[1] = 3e9;
  job();
  EXPECT_EQ(fb.ErrorID, kErrParamValue);
  read(pt_pnu(0x534));
  EXPECT_EQ(fb.ValueRead, before);  // nothing reached the drive
  write(pt_pnu(0x534), 0x06,
        65535);  // the top of Uint16 is sent (the drive then checks Pt534's own limit)
  EXPECT_NE(fb.ErrorID, kErrParamValue);
}

TEST_F(SinaParaTest, EveryErrorClassAsErrorId) {
  auto expect_err = [&](int no) {
    EXPECT_TRUE(fb.Error) << std::hex << no;
    EXPECT_EQ(fb.ErrorID, kErrParamResponse + no) << std::hex << fb.ErrorID.value;
    EXPECT_STREQ(fb.ErrorText.c_str(), param_error_text(static_cast<std::uint16_t>(no)));
  };
  read(0x2999);
  expect_err(0x00);
  write(922, 0x06, 3);
  expect_err(0x01);
  write(pt_pnu(0x317), 0x06, 0);
  expect_err(0x02);
  read(945, 64);
  expect_err(0x03);
  read(pt_pnu(0x317), 3);
  expect_err(0x04);
  write(pt_pnu(0x317), 0x07, 3000);
  expect_err(0x05);
  write(952, 0x06, 1);
  expect_err(0x06);
  write(0x3057, 0x06, 3);
  expect_err(0x14);
  read(pt_pnu(0x317), 0, 2);
  expect_err(0x16);
  fb.DoId = 2;
  read(922);
  expect_err(0x19);
  fb.DoId = 0;
  // 0x11: Pt53A ("Setup") while the pulses are on.
  power.Enable = true;
  run(5);
  write(pt_pnu(0x53A), 0x06, 1);
  expect_err(0x11);
  // Block input checks.
  write(pt_pnu(0x317), 0x44, 1);
  EXPECT_EQ(fb.ErrorID, kErrParamInput);
  // Wrong record index: the device refuses the record (16#83xx).
  fb.RecordIndex = 0x1234;
  read(922);
  EXPECT_EQ(fb.ErrorID, kErrParamRecord + static_cast<int>(io::RecordError::InvalidIndex));
  // The PROFINET base-mode local index works as well.
  fb.RecordIndex = kParamRecordIndexLocal;
  read(922);
  ASSERT_TRUE(fb.Done);
  EXPECT_EQ(fb.ValueRead, 111);
}

TEST_F(SinaParaTest, OfflineAndTimeout) {
  b.model->set_answering(false);
  run(2);
  read(922);
  EXPECT_EQ(fb.ErrorID, kErrOffline);
}

}  // namespace plc::drive::test
