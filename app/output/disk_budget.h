// The disk budget of `wobble run` and `wobble render`, beside the memory budget (app/scene/scene_limits.h): before
// anything is written, what the command will write is estimated (frames x files x bytes) and compared with the free
// space of the output folder's file system (statvfs of its nearest existing ancestor, for an unprivileged user) and
// with --max-disk; above either, the command is refused as bad input (exit 2), saying how much it needs, how much
// there is and what to change.
// The estimate is an upper bound wherever one exists before the run:
//   OBJ + MTL   per body per frame: the text at its longest (objTextSizeBound: about 1.5 times the real files)
//   PC2         per body: exact (32 bytes and 12 per point per frame), and its base mesh
//   PNG, EXR    per frame: the uncompressed size (file_size_bound.h); a picture compresses to less, by how much
//               depends on what it shows (a 1280 x 720 frame of jelly_slope: 2.4 times for PNG, 2.1 for EXR)
//   video       rough: 1 bit per pixel per frame (x264 at CRF 20: 0.3 on two 1280 x 720 frames of jelly_slope)
//   the rest    textures copied beside the meshes (their size), the scene and its files carried into OUT/scene
//               (carried_scene.h) and run.json
// Files of an earlier run that the command replaces are not counted as free space.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/scene_file.h"

namespace wobble {

struct DiskEstimate {
  struct Part {
    std::string what;  // "OBJ + MTL, 2 bodies x 300 frames"
    std::uint64_t bytes = 0;
    std::vector<std::string> changes;  // how to write less of it, besides fewer frames
  };
  int frames = 0;
  std::string fewer_frames;  // how to write fewer frames with this command
  std::vector<Part> parts;

  std::uint64_t bytes() const;
  std::string describe() const;  // "1.2 GB (OBJ + MTL ...: 1 GB; PNG ...: 200 MB)"
};

// What `wobble run` writes for frames first..last (1-based, inclusive) of the scene: meshes, point caches, textures,
// run.json, and its pictures.
DiskEstimate estimateRunOutput(const SceneFile& scene, int first, int last);

// What `wobble render` writes for frames first..last: the pictures (FrameOutput): PNG, EXR and the video, as the
// scene's [render] asks.
DiskEstimate estimateRenderOutput(const SceneFile& scene, int first, int last);

// Free bytes for an unprivileged user on the file system that holds path, or would hold it: its nearest existing
// ancestor ("." for a relative path none of whose folders exist yet).
std::uint64_t freeDiskSpace(const std::filesystem::path& path);

// The most bytes a command of this process may write: --max-disk when given (max_disk_option.h), else none beside the
// free space.
void setDiskBudget(std::uint64_t bytes);
std::optional<std::uint64_t> diskBudget();

// Throws InputError when the estimate is above the free space at out, or above diskBudget().
void checkDiskBudget(const DiskEstimate& estimate, const std::filesystem::path& out);

}  // namespace wobble
