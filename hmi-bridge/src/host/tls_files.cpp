#include "plc/hmi/tls_files.hpp"

#include <openssl/crypto.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <memory>

#include "plc/hmi/checked_file.hpp"
#include "plc/hmi/ipc/layout.hpp"

namespace plc::hmi {

namespace {

// The file's text, or "" with `err` set. `secret`: the private key's file,
// which only its owner may read. `max` counts the NUL of the settings' field.
std::string read_pem(const std::string& path, std::size_t max, bool secret, std::string& err) {
  const FileRules rules{secret ? "key file" : "certificate file", max - 1,
                        ", more than " + std::to_string(max - 1), secret,
                        "anyone who can read it can pose as this server"};
  return read_checked_file(path, rules, err).value_or(std::string());
}

struct BioFree {
  void operator()(BIO* b) const { BIO_free(b); }
};
struct X509Free {
  void operator()(X509* x) const { X509_free(x); }
};
struct KeyFree {
  void operator()(EVP_PKEY* k) const { EVP_PKEY_free(k); }
};

// An ASN1_TIME as OpenSSL prints it ("Dec  2 10:00:00 2026 GMT").
std::string asn1_time_text(const ASN1_TIME* t) {
  std::unique_ptr<BIO, BioFree> b(BIO_new(BIO_s_mem()));
  if (!b || ASN1_TIME_print(b.get(), t) != 1) return "?";
  char* data = nullptr;
  const long n = BIO_get_mem_data(b.get(), &data);
  return n > 0 ? std::string(data, std::size_t(n)) : "?";
}

}  // namespace

std::optional<TlsFiles> load_tls_files(const std::string& cert_path, const std::string& key_path,
                                       TlsFilesError& err, std::time_t now) {
  TlsFiles t;
  err = {};
  t.cert_pem = read_pem(cert_path, ipc::kMaxTlsCertPem, false, err.message);
  if (!err.message.empty()) return std::nullopt;
  t.key_pem = read_pem(key_path, ipc::kMaxTlsKeyPem, true, err.message);
  if (!err.message.empty()) {
    err.in_key = true;
    return std::nullopt;
  }
  auto fail = [&](bool in_key, std::string m) {
    OPENSSL_cleanse(t.key_pem.data(), t.key_pem.size());
    ERR_clear_error();
    err = {in_key, std::move(m)};
    return std::nullopt;
  };
  std::unique_ptr<BIO, BioFree> cb(BIO_new_mem_buf(t.cert_pem.data(), int(t.cert_pem.size())));
  std::unique_ptr<X509, X509Free> cert(cb ? PEM_read_bio_X509(cb.get(), nullptr, nullptr, nullptr)
                                          : nullptr);
  if (!cert) return fail(false, "certificate file '" + cert_path + "' holds no PEM certificate");
  std::unique_ptr<BIO, BioFree> kb(BIO_new_mem_buf(t.key_pem.data(), int(t.key_pem.size())));
  // No passphrase callback: an encrypted key is refused (plcrun starts
  // unattended).
  std::unique_ptr<EVP_PKEY, KeyFree> key(
      kb ? PEM_read_bio_PrivateKey(
               kb.get(), nullptr, [](char*, int, int, void*) { return 0; }, nullptr)
         : nullptr);
  if (!key)
    return fail(true, "key file '" + key_path +
                          "' holds no unencrypted PEM private key (openssl req ... -nodes)");
  if (X509_check_private_key(cert.get(), key.get()) != 1)
    return fail(true, "key file '" + key_path + "' is not the key of the certificate in '" +
                          cert_path + "'");
  // X509_cmp_time: -1 when the time is before `now`, 0 on an error.
  const ASN1_TIME* not_after = X509_get0_notAfter(cert.get());
  const ASN1_TIME* not_before = X509_get0_notBefore(cert.get());
  if (X509_cmp_time(not_after, &now) < 0)
    t.warning = "certificate in '" + cert_path + "' expired on " + asn1_time_text(not_after) +
                ": browsers will refuse it";
  else if (X509_cmp_time(not_before, &now) > 0)
    t.warning = "certificate in '" + cert_path + "' is not valid before " +
                asn1_time_text(not_before) + ": browsers will refuse it";
  ERR_clear_error();
  return t;
}

}  // namespace plc::hmi
