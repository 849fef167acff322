// `wobble frames SCENE_OR_OUT --chunks N`: the frame ranges of N pieces of a render, one "A:B" a line, so that GNU
// parallel or a Slurm array task picks its own range without arithmetic in shell (docs/farm-rendering.md, "Rendering on
// many machines"). From a run's folder the range is the frames the run wrote (OUT/run.json: what `wobble render` of
// that OUT/mesh can render); from a scene file, all the scene's frames (to plan before simulating). Contiguous pieces,
// as even as can be: the first (frames mod N) pieces get one frame more.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace wobble {

struct FramesOptions {
  std::filesystem::path source;  // a run's folder (with run.json) or a scene file
  int chunks = 1;
  std::optional<int> chunk;           // 1-based: only that piece's range
  std::optional<std::string> frames;  // "A:B": split only these
  std::vector<std::string> sets;      // overrides of a scene file (duration, fps)
};

// first..last in `chunks` contiguous ranges. Throws InputError when there are more chunks than frames.
std::vector<std::pair<int, int>> frameChunks(int first, int last, int chunks);

// The ranges to print. Throws InputError (exit 2) for a missing source, a folder without run.json, a bad --frames,
// --chunks or --chunk.
std::vector<std::pair<int, int>> framePieces(const FramesOptions& options);

}  // namespace wobble
