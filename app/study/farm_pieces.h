// Farm pieces of a sweep (`wobble study stability --piece I/N`, `wobble compare --piece I/N`): the sweep's work items
// (a study's rows, a comparison's variants), numbered as the one-machine run numbers them, are cut into N contiguous
// pieces (the first ones one item longer when N does not divide them, as `wobble frames --chunks`); piece I runs only
// its own, each item's result kept in OUT/pieces/<sweep>/item-NNNN.json as soon as it is done, and `--gather` reads
// them all back and writes the report (plots, video) a one-machine run writes, from the same numbers.
//
//   OUT/pieces/<sweep>.json   {"pieces": N, "key": K}: written by the first piece; every later piece in OUT must
//                             give the same N and the same sweep (K: a hash of everything its results depend on),
//                             else it is refused (exit 2) naming --piece and what is allowed
//   item-NNNN.json            {"key": K, "item": ...}: written atomically when the item is done; a piece run again
//                             (re-queued, preempted) keeps the items it finished and runs the rest (resumable)
//   item-NNNN.bin             the item's bulk result where it has one (an accuracy run's trajectory, a render study's
//                             image, exact floats), written before its .json, which holds its size and hash
//
// Each item is deterministic on its own (one thread per item), so its result is the bytes of the same item in a
// one-machine run, whichever piece, node or thread count ran it.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

namespace wobble {

struct Piece {
  int index = 1, count = 1;  // 1-based: piece index of count
};

// What a piece ran: its work items [first, last) of `items`, and how many of them an earlier run had finished.
struct PieceRun {
  std::size_t first = 0, last = 0, items = 0, kept = 0;
};

// "I/N" -> Piece. Throws InputError naming --piece for anything else (or I outside 1..N).
Piece parsePiece(const std::string& text);

class FarmPieces {
 public:
  // sweep: names the files ("stability", "compare"); key: the hash of the sweep's settings; items: how many.
  // With a piece: checks it against the folder (InputError: N above items, another N or another sweep there before)
  // and records the folder's N and key. Without (gather): the folder must hold a sweep of this key.
  FarmPieces(std::filesystem::path out, std::string sweep, std::string key, std::size_t items,
             std::optional<Piece> piece);

  int count() const { return count_; }  // N: the folder's pieces
  // The items [first, last) of the piece (all of them for gather).
  std::pair<std::size_t, std::size_t> range() const { return range_; }
  // A finished item's result, if the folder holds it for this sweep (and its data file, of the size recorded).
  std::optional<nlohmann::json> load(std::size_t item) const;
  // data: the item's bulk result, if any, kept in item-NNNN.bin.
  void store(std::size_t item, const nlohmann::json& result, std::string_view data = {}) const;
  // The data stored with a finished item. Throws InputError naming the file when it is missing or not the bytes
  // stored (altered since).
  std::string data(std::size_t item) const;
  // Gather: every item's result, in order. Throws InputError naming the pieces whose items are missing.
  std::vector<nlohmann::json> gather() const;

 private:
  std::filesystem::path itemFile(std::size_t item, const char* ending = ".json") const;
  std::filesystem::path folder_, manifest_;
  std::string sweep_, key_;
  std::size_t items_;
  int count_ = 1;
  std::pair<std::size_t, std::size_t> range_;
};

// The items [first, last) of piece `p` of `items` (contiguous; the first items % count pieces one longer).
std::pair<std::size_t, std::size_t> pieceItems(Piece p, std::size_t items);

}  // namespace wobble
