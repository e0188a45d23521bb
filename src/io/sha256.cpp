#include "seqtopo/io/sha256.hpp"

#include <openssl/evp.h>

#include <new>
#include <stdexcept>
#include <utility>

namespace seqtopo::io {

Sha256::Sha256() : context_(EVP_MD_CTX_new()) {
  if (context_ == nullptr) throw std::bad_alloc();
  if (EVP_DigestInit_ex(context_, EVP_sha256(), nullptr) != 1) {
    EVP_MD_CTX_free(context_);
    throw std::runtime_error("SHA-256: OpenSSL's EVP_DigestInit_ex failed");
  }
}

Sha256::~Sha256() { EVP_MD_CTX_free(context_); }

Sha256::Sha256(Sha256&& other) noexcept : context_(std::exchange(other.context_, nullptr)) {}

Sha256& Sha256::operator=(Sha256&& other) noexcept {
  std::swap(context_, other.context_);
  return *this;
}

void Sha256::update(std::string_view bytes) {
  if (context_ == nullptr) throw std::logic_error("SHA-256: update() after hex() or a move");
  if (bytes.empty()) return;  // an empty view may have no data pointer
  if (EVP_DigestUpdate(context_, bytes.data(), bytes.size()) != 1) {
    throw std::runtime_error("SHA-256: OpenSSL's EVP_DigestUpdate failed");
  }
}

std::string Sha256::hex() {
  if (context_ == nullptr) throw std::logic_error("SHA-256: hex() twice or after a move");
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  const int ok = EVP_DigestFinal_ex(context_, digest, &size);
  EVP_MD_CTX_free(std::exchange(context_, nullptr));
  if (ok != 1 || size != 32) throw std::runtime_error("SHA-256: OpenSSL's EVP_DigestFinal_ex failed");
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(64);
  for (unsigned int k = 0; k < size; ++k) {
    out.push_back(kDigits[digest[k] >> 4U]);
    out.push_back(kDigits[digest[k] & 0xFU]);
  }
  return out;
}

std::string sha256_hex(std::string_view bytes) {
  Sha256 h;
  h.update(bytes);
  return h.hex();
}

}  // namespace seqtopo::io
