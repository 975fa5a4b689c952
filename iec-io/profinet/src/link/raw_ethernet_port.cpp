#include "plc/profinet/link/raw_ethernet_port.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <net/if_arp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "poll_wait.hpp"

namespace plc::profinet {

namespace {

[[noreturn]] void fail(int fd, const std::string& msg) {
  if (fd >= 0) ::close(fd);
  throw LinkError(msg);
}

std::string why(int e) { return std::strerror(e); }

}  // namespace

RawEthernetPort::RawEthernetPort(const std::string& interface, RawEthernetOptions options)
    : interface_(interface) {
  const std::string where = "raw Ethernet on '" + interface + "'";
  if (interface.empty() || interface.size() >= IFNAMSIZ)
    fail(-1,
         where + ": not an interface name (1.." + std::to_string(IFNAMSIZ - 1) + " characters)");
  ifindex_ = static_cast<int>(::if_nametoindex(interface.c_str()));
  if (ifindex_ == 0)
    fail(-1, where + ": no such interface in this network namespace (`ip link` lists them)");
  // Protocol 0 until the filter is on, so nothing else queues up first.
  fd_ = ::socket(AF_PACKET, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) {
    const int e = errno;
    if (e == EPERM || e == EACCES)
      fail(-1, where +
                   ": no permission for a raw socket: PROFINET needs CAP_NET_RAW (run as "
                   "root, or `setcap cap_net_raw,cap_net_admin+ep` on the executable)");
    fail(-1, where + ": socket: " + why(e));
  }
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, interface.c_str(), interface.size());
  if (::ioctl(fd_, SIOCGIFHWADDR, &ifr) != 0) fail(fd_, where + ": no MAC address: " + why(errno));
  if (ifr.ifr_hwaddr.sa_family != ARPHRD_ETHER) fail(fd_, where + ": not an Ethernet interface");
  std::memcpy(mac_.data(), ifr.ifr_hwaddr.sa_data, 6);
  const int one = 1;

  // Bound to every protocol, not to 0x8892: the kernel strips a VLAN tag
  // on receive and, with no VLAN device to take the frame, clears it before
  // handing the frame to sockets bound to one EtherType; only "all"
  // sockets still see the tag in their auxdata. A classic BPF filter keeps
  // the rest out of the socket: EtherType 0x8892 at byte 12 (untagged, or
  // tag already taken off) or behind a tag still in the frame.
  sock_filter code[] = {
      {BPF_LD | BPF_H | BPF_ABS, 0, 0, 12},
      {BPF_JMP | BPF_JEQ | BPF_K, 4, 0, kEtherTypeProfinet},
      {BPF_JMP | BPF_JEQ | BPF_K, 0, 2, kEtherTypeVlan},
      {BPF_LD | BPF_H | BPF_ABS, 0, 0, 16},
      {BPF_JMP | BPF_JEQ | BPF_K, 1, 0, kEtherTypeProfinet},
      {BPF_RET | BPF_K, 0, 0, 0},
      {BPF_RET | BPF_K, 0, 0, 0x40000},
  };
  sock_fprog prog{static_cast<unsigned short>(sizeof code / sizeof code[0]), code};
  if (::setsockopt(fd_, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog) != 0)
    fail(fd_, where + ": cannot attach the 0x8892 filter: " + why(errno));
  // Our own frames are not for us (an "all" socket sees them go out).
  (void)::setsockopt(fd_, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one);
  sockaddr_ll sll{};
  sll.sll_family = AF_PACKET;
  sll.sll_protocol = htons(ETH_P_ALL);
  sll.sll_ifindex = ifindex_;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&sll), sizeof sll) != 0)
    fail(fd_, where + ": bind: " + why(errno));
  // The kernel takes VLAN tags off received frames and reports them here.
  if (::setsockopt(fd_, SOL_PACKET, PACKET_AUXDATA, &one, sizeof one) != 0)
    fail(fd_, where + ": PACKET_AUXDATA: " + why(errno));
  for (const Mac& group : {kDcpIdentifyMulticast, kDcpHelloMulticast}) {
    packet_mreq mr{};
    mr.mr_ifindex = ifindex_;
    mr.mr_type = PACKET_MR_MULTICAST;
    mr.mr_alen = 6;
    std::memcpy(mr.mr_address, group.data(), 6);
    if (::setsockopt(fd_, SOL_PACKET, PACKET_ADD_MEMBERSHIP, &mr, sizeof mr) != 0)
      fail(fd_, where + ": cannot join the DCP multicast " + to_string(group) + ": " + why(errno));
  }
  if (options.promiscuous) {
    packet_mreq pr{};
    pr.mr_ifindex = ifindex_;
    pr.mr_type = PACKET_MR_PROMISC;
    if (::setsockopt(fd_, SOL_PACKET, PACKET_ADD_MEMBERSHIP, &pr, sizeof pr) != 0)
      fail(fd_, where + ": cannot enter promiscuous mode: " + why(errno));
  }
}

RawEthernetPort::~RawEthernetPort() {
  if (fd_ >= 0) ::close(fd_);  // memberships end with the socket
}

bool RawEthernetPort::send(std::span<const std::uint8_t> frame) {
  const bool ok =
      frame.size() >= 14 && frame.size() <= kMaxFrameLength &&
      ::send(fd_, frame.data(), frame.size(), MSG_DONTWAIT) == static_cast<ssize_t>(frame.size());
  (ok ? counters_.sent : counters_.send_failed).fetch_add(1, std::memory_order_relaxed);
  return ok;
}

std::size_t RawEthernetPort::receive(std::span<std::uint8_t> buf,
                                     std::chrono::nanoseconds timeout) {
  // Bounded: each pass returns a frame or drops one.
  for (int pass = 0; pass < 64; ++pass) {
    if (!detail::wait_readable(fd_, pass == 0 ? timeout : timeout.zero())) return 0;
    // The MACs go to `head`, the rest of the frame to buf + 16: a tag the
    // kernel took off then goes back in front of the EtherType without
    // moving the frame. (So an untagged frame needs 4 bytes more room than
    // its length: a kMaxFrameLength buffer holds any frame.)
    std::uint8_t head[12];
    iovec iov[2] = {{head, sizeof head},
                    {buf.data() + (buf.size() >= 16 ? 16 : buf.size()),
                     buf.size() >= 16 ? buf.size() - 16 : 0}};
    alignas(cmsghdr) std::uint8_t control[CMSG_SPACE(sizeof(tpacket_auxdata))];
    sockaddr_ll from{};
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof from;
    msg.msg_iov = iov;
    msg.msg_iovlen = 2;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT | MSG_TRUNC);
    if (n < 0) return 0;
    if (from.sll_pkttype == PACKET_OUTGOING) continue;  // our own, seen by a tap
    bool tagged = false;
    std::uint16_t tpid = kEtherTypeVlan, tci = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level != SOL_PACKET || c->cmsg_type != PACKET_AUXDATA ||
          c->cmsg_len < CMSG_LEN(sizeof(tpacket_auxdata)))
        continue;
      tpacket_auxdata aux;
      std::memcpy(&aux, CMSG_DATA(c), sizeof aux);

      if (aux.tp_status & TP_STATUS_VLAN_VALID) {
        tagged = true;
        tci = aux.tp_vlan_tci;
        if (aux.tp_status & TP_STATUS_VLAN_TPID_VALID) tpid = aux.tp_vlan_tpid;
      }
    }
    const std::size_t len = static_cast<std::size_t>(n) + (tagged ? 4 : 0);
    if (n < 14 || len > buf.size() || static_cast<std::size_t>(n) - 12 > iov[1].iov_len) {
      counters_.rx_dropped.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    std::memcpy(buf.data(), head, 12);
    if (tagged) {
      buf[12] = static_cast<std::uint8_t>(tpid >> 8);
      buf[13] = static_cast<std::uint8_t>(tpid);
      buf[14] = static_cast<std::uint8_t>(tci >> 8);
      buf[15] = static_cast<std::uint8_t>(tci);
    } else {
      // The frame from byte 12 on landed at 16: close the gap.
      std::memmove(buf.data() + 12, buf.data() + 16, static_cast<std::size_t>(n) - 12);
    }
    counters_.received.fetch_add(1, std::memory_order_relaxed);
    return len;
  }
  return 0;
}

}  // namespace plc::profinet
