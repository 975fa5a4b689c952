// The shared memory between plcrun and plchmi (issue 22, "Process
// isolation"; hmi-bridge/include/plc/hmi/ipc/): the state region is
// read-only for plchmi by the kernel's seals, the rings and the blocks hold
// against a peer that writes anything, the cell layout decodes only when
// every count, index and offset fits.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <thread>

#include "plc/hmi/ipc/regions.hpp"
#include "plc/hmi/ipc/wire.hpp"

using namespace plc;
using namespace plc::hmi::ipc;

namespace {

CellLayout small_layout() {
  CellLayout l;
  l.cell = "ipc";
  l.layout_hash = 42;
  l.image_input = 8;
  l.image_output = 8;
  l.image_memory = 16;
  l.tasks = {{"fast", 1'000'000}, {"slow", 10'000'000}};
  l.devices = {{"tank1", "sim", "%IB0", "%QB0", 0, 2, 2}};
  CellLayout::Var a{"Tank.level",
                    VarType::INT,
                    io::IecAddress{io::Area::Input, io::AddrSize::Word, 0, 0},
                    0,
                    true,
                    false,
                    false,
                    false};
  CellLayout::Var b{"Tank.high_level", VarType::INT, std::nullopt, 0, true, true, false, false};
  CellLayout::Var c{"Tank.name", VarType::STRING, std::nullopt, 1, true, false, false, true};
  l.vars = {a, b, c};
  CellLayout::Slot s0;
  s0.task = 0;
  s0.buffer_size = 16;
  s0.items = {{0, 0}, {1, 8}};
  CellLayout::Slot s1;
  s1.task = 1;
  s1.buffer_size = 104;
  s1.items = {{2, 0}};
  l.slots = {s0, s1};
  l.start_alarms = {{"retain_cold_start", "retain", "cold start INSTEAD OF A WARM START", 7}};
  return l;
}

std::unique_ptr<Regions> make_regions(CellLayout& l) {
  Settings s;
  std::strcpy(s.url, "memq://");
  std::strcpy(s.prefix, "PLC");
  return Regions::create(s, l, 1234);
}

}  // namespace

// The state region is sealed: whoever holds its descriptor (plchmi) can map
// it read-only only; a writable mapping, write(2), ftruncate and a
// writable mprotect of a read-only mapping are refused by the kernel.
TEST(HmiIpc, StateRegionIsReadOnlyForEveryoneButItsCreator) {
  CellLayout l = small_layout();
  auto r = make_regions(l);
  const int fd = r->state_fd();
  EXPECT_EQ(mmap(nullptr, r->state_size(), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0), MAP_FAILED);
  EXPECT_EQ(errno, EPERM);
  EXPECT_EQ(pwrite(fd, "x", 1, 0), -1);
  EXPECT_EQ(ftruncate(fd, 0), -1);
  // Reopened through /proc (a new open file description): still sealed.
  const int again = open(("/proc/self/fd/" + std::to_string(fd)).c_str(), O_RDWR);
  ASSERT_GE(again, 0);
  EXPECT_EQ(mmap(nullptr, r->state_size(), PROT_READ | PROT_WRITE, MAP_SHARED, again, 0),
            MAP_FAILED);
  void* ro = mmap(nullptr, r->state_size(), PROT_READ, MAP_SHARED, again, 0);
  ASSERT_NE(ro, MAP_FAILED);
  EXPECT_NE(mprotect(ro, r->state_size(), PROT_READ | PROT_WRITE), 0);
  munmap(ro, r->state_size());
  close(again);
  // plchmi's view through the descriptors: the layout reads back.
  std::string err;
  auto bridge = Regions::attach(r->state_fd(), r->control_fd(), err);
  ASSERT_TRUE(bridge) << err;
  std::uint64_t generation = 0;
  const auto back = bridge->read_layout(generation, err);
  ASSERT_TRUE(back) << err;
  EXPECT_EQ(*back, l);
  EXPECT_EQ(generation, 2U);
  // plcrun itself still writes through its own mapping.
  r->rewrite(l);
  EXPECT_EQ(bridge->state().generation.load(), 4U);
}

TEST(HmiIpc, AttachRefusesWhatIsNotPlcrunsSharedMemory) {
  std::string err;
  const int fd = memfd_create("junk", MFD_CLOEXEC);
  ASSERT_EQ(ftruncate(fd, 65536), 0);
  EXPECT_FALSE(Regions::attach(fd, fd, err));
  EXPECT_NE(err.find("another kind"), std::string::npos) << err;
  EXPECT_FALSE(Regions::attach(-1, fd, err));
  close(fd);
}

// A consumer never reads garbage slots for a producer position that is not
// plausible, and a producer takes an implausible consumer position for a
// full ring.
TEST(HmiIpc, RingSurvivesAPeerThatWritesAnyPosition) {
  std::atomic<std::uint64_t> head{0}, tail{0};
  std::uint64_t slots[4] = {};
  Ring<std::uint64_t> ring(&head, &tail, slots, 4);
  for (std::uint64_t i = 1; i <= 4; ++i) EXPECT_TRUE(ring.push(i));
  EXPECT_FALSE(ring.push(5));  // full
  std::uint64_t out = 0;
  EXPECT_EQ(ring.pop(out), Ring<std::uint64_t>::Pop::Got);
  EXPECT_EQ(out, 1U);
  head.store(1'000'000);  // a hostile producer
  EXPECT_EQ(ring.pop(out), Ring<std::uint64_t>::Pop::Skipped);
  EXPECT_EQ(tail.load(), 1'000'000U);
  EXPECT_EQ(ring.pop(out), Ring<std::uint64_t>::Pop::Empty);
  head.store(5);  // behind the tail
  EXPECT_EQ(ring.pop(out), Ring<std::uint64_t>::Pop::Skipped);
  tail.store(~0ULL);  // a hostile consumer: the producer sees a full ring
  head.store(0);
  EXPECT_FALSE(ring.push(9));
}

// Two threads, the ring's only producer and consumer: every record arrives
// once and in order (ThreadSanitizer checks the memory order).
TEST(HmiIpc, RingCarriesEveryRecordInOrderBetweenTwoThreads) {
  std::atomic<std::uint64_t> head{0}, tail{0};
  std::uint64_t slots[8] = {};
  Ring<std::uint64_t> producer(&head, &tail, slots, 8), consumer(&head, &tail, slots, 8);
  constexpr std::uint64_t kN = 20000;
  // Both loops bounded, and the producer stops when the consumer gives up
  // (a failed check, or its bound on a loaded machine): join never hangs.
  // A side that finds the ring full or empty yields, so that on a shared
  // core the other side gets to run.
  std::atomic<bool> consumer_done{false};
  std::thread p([&] {
    for (std::uint64_t i = 1, tries = 0; i <= kN && !consumer_done.load() && tries < 100'000'000;
         ++tries) {
      if (producer.push(i))
        ++i;
      else
        std::this_thread::yield();
    }
  });
  std::uint64_t expect = 1;
  bool in_order = true;
  for (int spins = 0; expect <= kN && in_order && spins < 100'000'000; ++spins) {
    std::uint64_t v = 0;
    if (consumer.pop(v) == Ring<std::uint64_t>::Pop::Got) {
      in_order = v == expect;
      EXPECT_EQ(v, expect);
      ++expect;
    } else {
      std::this_thread::yield();
    }
  }
  consumer_done = true;
  p.join();
  EXPECT_EQ(expect, kN + 1);
}

// The seqlock block: a reader gets a whole copy or none, never a mix of two
// writes (the writer rewrites a block of equal bytes, each write another
// byte value).
TEST(HmiIpc, SeqBlockReadsAreNeverTorn) {
  std::vector<std::uint64_t> mem(64, 0);
  SeqBlock block(reinterpret_cast<unsigned char*>(mem.data()), 64 * 8 - SeqBlock::kHeader);
  std::vector<unsigned char> out;
  EXPECT_FALSE(block.read(out));                                   // never written
  EXPECT_FALSE(block.write(std::vector<unsigned char>(1000, 1)));  // does not fit
  std::atomic<bool> stop{false};
  std::atomic<int> writes{0};
  std::thread w([&] {
    for (unsigned char v = 1; !stop.load(); ++v) {
      block.write(std::vector<unsigned char>(400, v));
      writes.fetch_add(1);
    }
  });
  // Reads while the writer keeps writing: until 1000 whole copies were read
  // during the writes. Bounded in time, not in tries: on a loaded machine
  // the writer may lose its core mid-write for longer than any fixed number
  // of failed reads takes (every read then finds the block being written).
  int whole = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (whole < 1000 && std::chrono::steady_clock::now() < deadline) {
    if (writes.load() == 0) {
      std::this_thread::yield();
      continue;
    }
    if (block.read(out)) {
      ASSERT_EQ(out.size(), 400U);
      ASSERT_TRUE(
          std::all_of(out.begin(), out.end(), [&](unsigned char c) { return c == out[0]; }));
      ++whole;
    }
  }
  stop = true;
  w.join();
  EXPECT_EQ(whole, 1000);
}

// Every field of the layout is checked on the way in: a count beyond the
// bytes, a type or address enum out of range, an index past its table, a
// slot or an item outside its memory, trailing bytes.
TEST(HmiIpc, LayoutDecodeRefusesEveryInconsistency) {
  CellLayout l = small_layout();
  auto r = make_regions(l);  // places the slots
  const std::vector<unsigned char> good = l.encode();
  std::string err;
  ASSERT_TRUE(CellLayout::decode(good.data(), good.size(), r->state_size(), err)) << err;
  // Every truncation fails.
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_FALSE(CellLayout::decode(good.data(), n, r->state_size(), err)) << n;
  auto changed = [&](auto f) {
    CellLayout c = l;
    f(c);
    const auto b = c.encode();
    std::string why;
    const bool ok = CellLayout::decode(b.data(), b.size(), r->state_size(), why).has_value();
    return ok ? std::string() : why;
  };
  EXPECT_NE(changed([](CellLayout& c) { c.vars[0].type = VarType(17); }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.vars[0].address->bit = 9; }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.vars[0].task = 2; }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.devices[0].task = 5; }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.slots[0].items[0].var = 3; }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.slots[0].items[1].offset = 15; }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.slots[1].buffer_size = 8; }), "");  // STRING overhangs
  EXPECT_NE(changed([&](CellLayout& c) { c.slots[0].buffer = r->state_size(); }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.slots[0].header = 3; }), "");
  EXPECT_NE(changed([](CellLayout& c) { c.slots[0].task = 7; }), "");
  std::vector<unsigned char> longer = good;
  longer.push_back(0);
  EXPECT_FALSE(CellLayout::decode(longer.data(), longer.size(), r->state_size(), err));
  // A count of 2^32-1 variables allocates nothing.
  WireOut w;
  w.str("x");
  w.u64(0);
  w.u32(0);
  w.u32(0);
  w.u32(0);
  w.u32(0xffffffffU);
  EXPECT_FALSE(CellLayout::decode(w.bytes().data(), w.bytes().size(), 1 << 20, err));
}
