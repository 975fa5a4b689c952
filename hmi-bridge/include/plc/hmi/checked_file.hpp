// Reading a small file that plcrun trusts at start (the HMI key,
// command_auth.cpp; the web HMI's TLS certificate and key, tls_files.cpp)
// with the checks they share: what was opened is what is checked (fstat,
// so it cannot be swapped in between), a FIFO in its place does not hang
// the start, its size is bounded, and a secret's file is readable by its
// owner only, who is this user or root.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace plc::hmi {

struct FileRules {
  std::string what;           // "key file": the messages' subject
  std::size_t max_bytes;      // larger files are refused unread
  std::string too_large;      // after "<what> '<path>' is N bytes"
  bool secret = false;        // mode without group/other bits, owner this user or root
  std::string exposure = {};  // secret: what anyone who could read it could do
};

// The file's text, or nullopt with `err` set, worded after `rules`. The
// text of a secret is the caller's to wipe.
std::optional<std::string> read_checked_file(const std::string& path, const FileRules& rules,
                                             std::string& err);

}  // namespace plc::hmi
