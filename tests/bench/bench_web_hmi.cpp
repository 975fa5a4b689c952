// The web HMI's costs (issue 27). Prints `name: value unit` lines:
// - web_hmi_bridge_cpu_10_pages: the CPU of the bridge's thread and of the
//   web server's thread together, in percent of one core, while 10 pages
//   (WebSocket clients on loopback, each on its own thread) watch 1,000
//   variables that all change every scan, at the bridge's rate 10/s;
//   web_hmi_web_thread_cpu_10_pages: the web thread alone;
//   web_hmi_bridge_cpu_no_pages: the bridge's thread without the web
//   server, the same cell, for comparison;
// - web_hmi_scan_cpu_10_pages / _no_pages: the scan thread's CPU per scan
//   (1 ms task, real time) in the two runs: a scan never waits for a page,
//   it copies the published variables when the bridge asks, whoever watches;
// - web_hmi_latency_{median,p99,max}: from the scan's copy of the values
//   (values_t.scan_utime) to the page's receipt of the JSON message, over
//   all 10 pages;
// - web_hmi_bytes_per_page: what one page received per second.
// In one process (the bridge as plchmi runs it, on its own thread; the web
// server on its own): each thread's CPU from /proc/self/task/TID/schedstat.
#include <pthread.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
// Boost 1.74's asio/awaitable.hpp uses std::exchange without <utility>.
#include <utility>
// clang-format off: <utility> first
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
// clang-format on

#include "plc/hmi/bridge.hpp"
#include "plc/hmi/host.hpp"
#include "plc/hmi/utime.hpp"
#include "plc/hmi/web/web_server.hpp"
#include "plc/program.hpp"
#include "plc_bench/thousand_vars_cell.hpp"

namespace {

using namespace plc;
namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

// A thread's CPU time so far in seconds, to the nanosecond: the first
// field of /proc/self/task/TID/schedstat (stat's utime and stime count
// 10 ms ticks, too coarse for a 2 us scan).
double thread_cpu(pid_t tid) {
  std::ifstream f("/proc/self/task/" + std::to_string(tid) + "/schedstat");
  double ns = 0;
  f >> ns;
  return ns / 1e9;
}

// The thread of this process called `name` (pthread_setname_np), 0: none.
pid_t tid_named(const std::string& name) {
  for (const auto& e : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream f(e.path() / "comm");
    std::string comm;
    std::getline(f, comm);
    if (comm == name) return pid_t(std::stol(e.path().filename().string()));
  }
  return 0;
}

struct Result {
  double bridge_cpu = 0, web_cpu = 0, scan_cpu_per_scan_ns = 0, bytes_per_page = 0;
  std::vector<std::int64_t> latency;
};

Result run(int pages, std::chrono::seconds span) {
  Runtime rt(parse_cell_config(bench::kThousandVarsCell, "bench.yaml"));
  hmi::Host::Options o;
  o.mode = hmi::Host::Mode::Thread;
  hmi::Host host(bench::thousand_vars_hmi("memq://", 10), "bench.yaml", o);
  host.attach(rt);
  hmi::Bridge bridge(host.regions().view(), host.doorbell());
  std::unique_ptr<hmi::web::WebServer> web;
  if (pages > 0) {
    hmi::web::WebOptions wo;
    wo.port = 0;
    web = std::make_unique<hmi::web::WebServer>(bridge, wo);
    bridge.set_tap(web.get());
    web->start();
  }
  rt.start(io::ClockMode::RealTime);
  host.start();
  std::atomic<bool> stop{false};
  std::atomic<pid_t> bridge_tid{0}, scan_tid{0};
  std::thread bt([&] {
    bridge_tid = pid_t(syscall(SYS_gettid));
    bridge.publish_description();
    bridge.run(stop);
  });
  std::atomic<std::uint64_t> scans{0};
  std::thread st([&] {
    scan_tid = pid_t(syscall(SYS_gettid));
    rt.run(io::ClockMode::RealTime, span + std::chrono::seconds(2));
  });
  std::mutex mu;
  std::vector<std::int64_t> latency;
  std::atomic<std::uint64_t> bytes{0};
  std::atomic<bool> measuring{false};
  std::vector<std::thread> clients;
  for (int i = 0; i < pages; ++i)
    clients.emplace_back([&, port = web->port()] {
      asio::io_context ioc;
      const std::string host_port = "127.0.0.1:" + std::to_string(port);
      std::string cookie;
      {
        tcp::socket s(ioc);
        s.connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
        http::request<http::string_body> req{http::verb::get, "/api/session", 11};
        req.set(http::field::host, host_port);
        http::write(s, req);
        beast::flat_buffer b;
        http::response<http::string_body> res;
        http::read(s, b, res);
        const std::string c(res[http::field::set_cookie]);
        cookie = c.substr(0, c.find(';'));
      }
      websocket::stream<tcp::socket> ws(ioc);
      ws.next_layer().connect(
          {asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
      ws.set_option(websocket::stream_base::decorator([&](websocket::request_type& r) {
        r.set(http::field::origin, "http://" + host_port);
        r.set(http::field::cookie, cookie);
      }));
      ws.handshake(host_port, "/api/ws");
      beast::flat_buffer b;
      while (!stop) {
        beast::error_code ec;
        ws.read(b, ec);
        if (ec) break;
        const std::string m = beast::buffers_to_string(b.data());
        b.clear();
        if (!measuring) continue;
        bytes += m.size();
        const auto at = m.find("\"scan_utime\":");
        if (at == std::string::npos || m.find("\"t\":\"values\"") != 1) continue;
        const std::int64_t d = hmi::utime_now() - std::stoll(m.substr(at + 13));
        std::lock_guard<std::mutex> l(mu);
        latency.push_back(d);
      }
    });
  // One second to settle (descriptions, first full snapshots), then the span.
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const pid_t web_tid = pages > 0 ? tid_named("plchmi-web") : 0;
  const double b0 = thread_cpu(bridge_tid), w0 = web_tid ? thread_cpu(web_tid) : 0,
               s0 = thread_cpu(scan_tid);
  const auto scans0 = rt.tasks()[0]->stats.snapshot().scans;
  measuring = true;
  std::this_thread::sleep_for(span);
  measuring = false;
  const double b1 = thread_cpu(bridge_tid), w1 = web_tid ? thread_cpu(web_tid) : 0,
               s1 = thread_cpu(scan_tid);
  const auto scans1 = rt.tasks()[0]->stats.snapshot().scans;
  st.join();
  stop = true;
  bt.join();
  if (web) {
    bridge.set_tap(nullptr);
    web->stop();  // closes the pages: their reads end
  }
  for (auto& c : clients) c.join();
  host.stop();
  rt.finish();
  Result r;
  const double secs = double(span.count());
  r.bridge_cpu = 100.0 * (b1 - b0) / secs;
  r.web_cpu = 100.0 * (w1 - w0) / secs;
  r.scan_cpu_per_scan_ns = (s1 - s0) * 1e9 / double(std::max<std::uint64_t>(1, scans1 - scans0));
  r.bytes_per_page = pages ? double(bytes) / secs / pages : 0;
  r.latency = std::move(latency);
  std::sort(r.latency.begin(), r.latency.end());
  return r;
}

}  // namespace

int main() {
  const char* env = std::getenv("PLC_BENCH_WEB_SECONDS");
  const std::chrono::seconds span(env ? std::max(1, std::atoi(env)) : 10);
  const Result none = run(0, span);
  const Result ten = run(10, span);
  std::printf("web_hmi_bridge_cpu_10_pages: %.2f %%\n", ten.bridge_cpu + ten.web_cpu);
  std::printf("web_hmi_web_thread_cpu_10_pages: %.2f %%\n", ten.web_cpu);
  std::printf("web_hmi_bridge_cpu_no_pages: %.2f %%\n", none.bridge_cpu);
  std::printf("web_hmi_scan_cpu_10_pages: %.0f ns\n", ten.scan_cpu_per_scan_ns);
  std::printf("web_hmi_scan_cpu_no_pages: %.0f ns\n", none.scan_cpu_per_scan_ns);
  std::printf("web_hmi_bytes_per_page: %.0f B/s\n", ten.bytes_per_page);
  if (!ten.latency.empty()) {
    const auto& l = ten.latency;
    std::printf("web_hmi_latency_median: %lld us\n", static_cast<long long>(l[l.size() / 2]));
    std::printf("web_hmi_latency_p99: %lld us\n",
                static_cast<long long>(l[std::min(l.size() - 1, l.size() * 99 / 100)]));
    std::printf("web_hmi_latency_max: %lld us\n", static_cast<long long>(l.back()));
    std::fprintf(stderr, "bench_web_hmi: %zu messages over 10 pages in %lld s\n", l.size(),
                 static_cast<long long>(span.count()));
  }
  return 0;
}
