// The web HMI's certificate and private key (hmi: web: tls:, docs/config.md),
// read and checked by plcrun at the bridge's start: plchmi runs as another,
// unprivileged user and gets their PEM texts through the state region
// (ipc::Settings), never the paths.
#pragma once

#include <ctime>
#include <optional>
#include <string>

namespace plc::hmi {

struct TlsFiles {
  std::string cert_pem;  // the server's certificate first, then its chain
  std::string key_pem;
  // Not empty when the certificate is outside its validity period at `now`
  // (expired, or not valid yet): browsers refuse it, but the cell starts
  // (an HMI certificate never stops a PLC); plcrun logs it.
  std::string warning;
};

struct TlsFilesError {
  bool in_key = false;  // the key's line, else the cert's
  std::string message;
};

// Reads both files (regular files within ipc::kMaxTlsCertPem /
// kMaxTlsKeyPem). Refused, with the reason: a file that cannot be read or
// holds no PEM certificate / private key; a key file that group or others
// may read or write, or that belongs to another user than this process's
// (or root) (as the HMI key file, command_auth.hpp load_key); a key that is
// not the certificate's.
std::optional<TlsFiles> load_tls_files(const std::string& cert_path, const std::string& key_path,
                                       TlsFilesError& err, std::time_t now = std::time(nullptr));

}  // namespace plc::hmi
