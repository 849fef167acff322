#include "app/study/farm_pieces.h"

#include <charconv>
#include <cstdio>
#include <fstream>
#include <vector>

#include "app/scene/input_error.h"
#include "io/atomic_file.h"
#include "io/content_hash.h"
#include "io/text_file.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace wobble {

Piece parsePiece(const std::string& text) {
  Piece p{0, 0};
  const auto slash = text.find('/');
  const auto number = [](std::string_view s, int& to) {
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), to);
    return error == std::errc() && end == s.data() + s.size();
  };
  if (slash == std::string::npos || !number(std::string_view(text).substr(0, slash), p.index) ||
      !number(std::string_view(text).substr(slash + 1), p.count) || p.count < 1)
    throw InputError("--piece '" + text + "': expected I/N, piece I of N (1 <= I <= N), e.g. --piece 3/8");
  if (p.index < 1 || p.index > p.count)
    throw InputError("--piece " + text + ": I must be 1 to " + std::to_string(p.count) + " (piece I of N)");
  return p;
}

std::pair<std::size_t, std::size_t> pieceItems(Piece p, std::size_t items) {
  const std::size_t n = std::size_t(p.count), base = items / n, longer = items % n, i = std::size_t(p.index - 1);
  const std::size_t first = i * base + std::min(i, longer);
  return {first, first + base + (i < longer ? 1 : 0)};
}

FarmPieces::FarmPieces(fs::path out, std::string sweep, std::string key, std::size_t items, std::optional<Piece> piece)
    : folder_(out / "pieces" / sweep),
      manifest_(out / "pieces" / (sweep + ".json")),
      sweep_(std::move(sweep)),
      key_(std::move(key)),
      items_(items),
      range_{0, items} {
  std::optional<json> earlier;
  if (fs::is_regular_file(manifest_)) {
    try {
      earlier = json::parse(io::readTextFile(manifest_));
      earlier->at("pieces").get<int>();
      earlier->at("key").get<std::string>();
    } catch (const json::exception& e) {
      throw InputError(manifest_.string() + ": not a wobble pieces file (" + e.what() + "); remove OUT/pieces");
    }
  }
  const std::string what =
      piece ? "--piece " + std::to_string(piece->index) + "/" + std::to_string(piece->count) : std::string("--gather");
  if (earlier && earlier->at("key") != key_)
    throw InputError(what + ": " + manifest_.string() + " holds the pieces of another " + sweep_ +
                     " (other scene, flags or settings); allowed: the same command as those pieces, or another --out");
  if (!piece) {
    if (!earlier)
      throw InputError("--gather: " + manifest_.string() + " not found: no piece of this " + sweep_ +
                       " ran into this folder (run each --piece I/N first)");
    count_ = earlier->at("pieces").get<int>();
    return;
  }
  if (std::size_t(piece->count) > items)
    throw InputError(what + ": N must be 1 to " + std::to_string(items) + " (the " + sweep_ + " has " +
                     std::to_string(items) + " work items, one a piece at most)");
  if (earlier && earlier->at("pieces").get<int>() != piece->count) {
    const int n = earlier->at("pieces").get<int>();
    throw InputError(what + ": this folder holds pieces of " + std::to_string(n) + " (" + manifest_.string() +
                     "); allowed: --piece I/" + std::to_string(n) + " with I from 1 to " + std::to_string(n) +
                     ", or another --out");
  }
  count_ = piece->count;
  range_ = pieceItems(*piece, items);
  fs::create_directories(folder_);
  if (!earlier) io::writeFileAtomically(manifest_, json{{"pieces", count_}, {"key", key_}}.dump(2) + "\n");
}

fs::path FarmPieces::itemFile(std::size_t item, const char* ending) const {
  char name[40];
  std::snprintf(name, sizeof name, "item-%04zu%s", item + 1, ending);
  return folder_ / name;
}

std::optional<json> FarmPieces::load(std::size_t item) const {
  const fs::path file = itemFile(item);
  if (!fs::is_regular_file(file)) return std::nullopt;
  try {
    json j = json::parse(io::readTextFile(file));
    if (j.at("key") != key_) return std::nullopt;
    std::error_code error;
    if (j.contains("data") &&
        fs::file_size(itemFile(item, ".bin"), error) != j.at("data").at("bytes").get<std::size_t>())
      return std::nullopt;  // its data lost or cut short: run the item again
    return j.at("item");
  } catch (const json::exception&) {
    return std::nullopt;  // not ours, or not whole: run the item again
  }
}

void FarmPieces::store(std::size_t item, const json& result, std::string_view data) const {
  json j{{"key", key_}, {"item", result}};
  if (!data.empty()) {
    io::writeFileAtomically(itemFile(item, ".bin"), data);  // before the .json that says the item is done
    j["data"] = {{"bytes", data.size()}, {"xxh3", io::hashOf(data)}};
  }
  io::writeFileAtomically(itemFile(item), j.dump(1) + "\n");
}

std::string FarmPieces::data(std::size_t item) const {
  const fs::path file = itemFile(item, ".bin");
  std::string bytes, recorded;
  try {
    recorded = json::parse(io::readTextFile(itemFile(item))).at("data").at("xxh3").get<std::string>();
    bytes = io::readTextFile(file);
  } catch (const std::exception&) {
  }
  if (recorded.empty() || io::hashOf(bytes) != recorded)
    throw InputError(file.string() + ": missing or altered since its piece wrote it (" + itemFile(item).string() +
                     " holds its hash); run that piece again after removing both files");
  return bytes;
}

std::vector<json> FarmPieces::gather() const {
  std::vector<json> out;
  std::vector<int> missing_pieces;
  for (int p = 1; p <= count_; ++p) {
    const auto [first, last] = pieceItems({p, count_}, items_);
    bool whole = true;
    for (std::size_t i = first; i < last; ++i) {
      std::optional<json> j = load(i);
      whole = whole && j.has_value();
      if (j) out.push_back(std::move(*j));
    }
    if (!whole) missing_pieces.push_back(p);
  }
  if (!missing_pieces.empty()) {
    std::string list;
    for (const int p : missing_pieces)
      list += (list.empty() ? "" : ", ") + std::to_string(p) + "/" + std::to_string(count_);
    throw InputError("--gather: " + folder_.string() + " lacks results of piece(s) " + list +
                     ": run them (--piece I/N; a piece run again resumes) before gathering");
  }
  return out;
}

}  // namespace wobble
