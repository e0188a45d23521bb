#pragma once
// SHA-256 (FIPS 180-4), for the manifest of an output folder: incremental, or of bytes in memory. OpenSSL's
// libcrypto computes it (with the CPU's SHA instructions where there are some): the manifest hashes every
// output, a hundred megabytes for a large map.
#include <string>
#include <string_view>

struct evp_md_ctx_st;  // OpenSSL's EVP_MD_CTX, kept out of this header

namespace seqtopo::io {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(Sha256&& other) noexcept;
  Sha256& operator=(Sha256&& other) noexcept;
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(std::string_view bytes);
  // The digest as 64 lowercase hex digits; the object is spent afterwards.
  std::string hex();

 private:
  evp_md_ctx_st* context_ = nullptr;
};

// sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
std::string sha256_hex(std::string_view bytes);

}  // namespace seqtopo::io
