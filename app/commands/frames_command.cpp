#include "app/commands/frames_command.h"

#include "app/commands/frame_range.h"
#include "app/output/run_record.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"

namespace fs = std::filesystem;

namespace wobble {

std::vector<std::pair<int, int>> frameChunks(int first, int last, int chunks) {
  const int count = last - first + 1;
  const std::string range = std::to_string(first) + ":" + std::to_string(last);
  if (chunks < 1 || chunks > count)
    throw InputError("--chunks " + std::to_string(chunks) + ": must be 1 to " + std::to_string(count) +
                     " (one frame a piece at most: frames " + range + ")");
  std::vector<std::pair<int, int>> pieces;
  for (int i = 0, a = first; i < chunks; ++i) {
    const int size = count / chunks + (i < count % chunks ? 1 : 0);
    pieces.emplace_back(a, a + size - 1);
    a += size;
  }
  return pieces;
}

std::vector<std::pair<int, int>> framePieces(const FramesOptions& options) {
  std::pair<int, int> range;
  if (fs::is_directory(options.source)) {
    if (!options.sets.empty())
      throw InputError("--set: only with a scene file (" + options.source.string() + "/run.json has the run's)");
    const RunRecord run = readRunRecord(options.source, "; give its scene file instead");
    range = options.frames ? parseFrameRange(*options.frames, run.first_frame, run.last_frame, run.framesText())
                           : std::pair{run.first_frame, run.last_frame};
  } else if (fs::is_regular_file(options.source)) {
    const int count = loadScene(options.source, options.sets).frameCount();
    range = options.frames ? parseFrameRange(*options.frames, count) : std::pair{1, count};
  } else {
    throw InputError(options.source.string() + ": no such file or folder (a run's output folder or a scene file)");
  }
  std::vector<std::pair<int, int>> pieces = frameChunks(range.first, range.second, options.chunks);
  if (!options.chunk) return pieces;
  if (*options.chunk < 1 || *options.chunk > options.chunks)
    throw InputError("--chunk " + std::to_string(*options.chunk) + ": must be 1 to " + std::to_string(options.chunks) +
                     " (--chunks)");
  return {pieces[*options.chunk - 1]};
}

}  // namespace wobble
