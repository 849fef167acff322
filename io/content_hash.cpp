#include "io/content_hash.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <xxhash.h>

namespace wobble::io {

struct ContentHash::State {
  XXH3_state_t* xxh = XXH3_createState();
  ~State() { XXH3_freeState(xxh); }
};

ContentHash::ContentHash() : state_(std::make_unique<State>()) {
  if (!state_->xxh) throw std::bad_alloc();
  XXH3_128bits_reset(state_->xxh);
}

ContentHash::~ContentHash() = default;

void ContentHash::add(std::span<const std::byte> bytes) {
  if (!bytes.empty()) XXH3_128bits_update(state_->xxh, bytes.data(), bytes.size());
}

void ContentHash::add(std::string_view text) {
  add(std::uint64_t(text.size()));
  add(std::as_bytes(std::span<const char>(text.data(), text.size())));
}

void ContentHash::addFile(const std::filesystem::path& file) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(file.c_str(), "rb"), std::fclose);
  if (!in) throw std::runtime_error(file.string() + ": cannot read: " + std::strerror(errno));
  std::vector<std::byte> buffer(1 << 16);
  std::uint64_t total = 0;
  while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), in.get())) {
    add(std::span<const std::byte>(buffer.data(), n));
    total += n;
  }
  if (std::ferror(in.get())) throw std::runtime_error(file.string() + ": cannot read: " + std::strerror(errno));
  add(total);  // the length last: a file and the same bytes plus a suffix differ
}

std::string ContentHash::hex() const {
  XXH128_canonical_t canonical;
  XXH128_canonicalFromHash(&canonical, XXH3_128bits_digest(state_->xxh));
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  for (unsigned char byte : canonical.digest) out += kDigits[byte >> 4], out += kDigits[byte & 15];
  return out;
}

std::string hashOf(std::string_view text) {
  ContentHash h;
  h.add(text);
  return h.hex();
}

}  // namespace wobble::io
