// ContentHash: a 128-bit digest of bytes fed in pieces (xxHash's XXH3, Debian's libxxhash), as 32 hex digits. A
// stable key for "is this the same input as before": cached study references, and the settings a frame was rendered
// with (app/output/picture_key.h). Not cryptographic: it guards against accidents, not against an adversary.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace wobble::io {

class ContentHash {
 public:
  ContentHash();
  ~ContentHash();
  ContentHash(const ContentHash&) = delete;
  ContentHash& operator=(const ContentHash&) = delete;

  void add(std::span<const std::byte> bytes);
  // Text is added with its length first, so ("ab", "c") and ("a", "bc") differ.
  void add(std::string_view text);
  // A number, as its bytes (a struct's fields are added one by one: its padding is not data).
  template <class T>
  requires std::is_arithmetic_v<T>
  void add(T value) { add(std::as_bytes(std::span<const T>(&value, 1))); }
  // An array of numbers, with its length first.
  template <class T>
  requires std::is_arithmetic_v<T>
  void addArray(std::span<const T> values) {
    add(std::uint64_t(values.size()));
    add(std::as_bytes(values));
  }
  // A whole file's bytes; throws std::runtime_error naming the file when it cannot be read.
  void addFile(const std::filesystem::path& file);

  std::string hex() const;  // 32 lowercase hex digits of the bytes added so far

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The digest of one string: hashOf(text) == ContentHash{}.add(text).hex().
std::string hashOf(std::string_view text);

}  // namespace wobble::io
