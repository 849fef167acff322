#include "app/output/disk_budget.h"

#include <algorithm>
#include <system_error>

#include "app/output/carried_scene.h"
#include "app/output/obj_sequence.h"
#include "app/output/pc2.h"
#include "app/output/picture_key.h"
#include "app/scene/input_error.h"
#include "image/file_size_bound.h"
#include "io/content_hash.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

constexpr std::uint64_t kRunJsonBytes = 64 * 1024;  // a few KB: its keys are fixed, its numbers short
constexpr double kVideoBytesPerPixel = 1.0 / 8;     // rough: 1 bit per pixel per frame
std::uint64_t budget_override = 0;                  // --max-disk; 0: not given

std::string plural(std::uint64_t n, const std::string& one, const std::string& many = "") {
  return std::to_string(n) + " " + (n == 1 ? one : many.empty() ? one + "s" : many);
}

// A frame's picture text as PictureKey writes it: both digests have the length of any digest.
std::map<std::string, std::string> pictureText() {
  return {{PictureKey::kSettingsName, io::hashOf("")}, {PictureKey::kFrameName, io::hashOf("")}};
}

// The pictures of `frames` frames; `none` is how the command writes none ("" when it cannot).
void addPictures(DiskEstimate& e, const SceneFile& scene, int frames, const std::string& none) {
  const RenderOptionsConfig& o = scene.render.options;
  const int w = scene.render.camera.resolution[0], h = scene.render.camera.resolution[1];
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  std::vector<std::string> changes;
  if (!none.empty()) changes.push_back(none);
  changes.push_back("a smaller --resolution (" + size + " now)");
  const std::uint64_t n = std::uint64_t(std::max(0, frames));
  if (o.png)
    e.parts.push_back({"PNG, " + plural(n, "frame") + " at " + size + " (at most their uncompressed size)",
                       n * image::pngSizeBound(w, h, 3, pictureText()), changes});
  changes.push_back("no EXR (--render png)");
  if (o.exr)
    e.parts.push_back({"EXR, " + plural(n, "frame") + " at " + size + " (at most their uncompressed size)",
                       n * image::exrSizeBound(w, h, o.denoise, pictureText()), changes});
  if (o.png && o.video)
    e.parts.push_back({"video, " + plural(n, "frame") + " (roughly)",
                       std::uint64_t(double(n) * w * h * kVideoBytesPerPixel),
                       {"no video (render.video = false)"}});
}

DiskEstimate framesOf(int first, int last, const std::string& how) {
  DiskEstimate e;
  e.frames = std::max(0, last - first + 1);
  e.fewer_frames = "fewer frames (" + how + "; " + plural(std::uint64_t(e.frames), "frame") + " now)";
  return e;
}

}  // namespace

std::uint64_t DiskEstimate::bytes() const {
  std::uint64_t sum = 0;
  for (const Part& p : parts) sum += p.bytes;
  return sum;
}

std::string DiskEstimate::describe() const {
  std::string text = formatBytes(bytes()) + " (";
  for (std::size_t i = 0; i < parts.size(); ++i)
    text += (i ? "; " : "") + parts[i].what + ": " + formatBytes(parts[i].bytes);
  return text + ")";
}

DiskEstimate estimateRunOutput(const SceneFile& scene, int first, int last) {
  DiskEstimate e = framesOf(first, last, "--frames A:B, a shorter simulation.duration or a lower simulation.fps");
  const auto& bodies = scene.system->bodies();
  const std::uint64_t frames = std::uint64_t(e.frames);
  std::uint64_t obj = 0, pc2 = 0, other = kRunJsonBytes;
  for (const BodySlot& slot : bodies) {
    if (!scene.write_obj && !scene.write_pc2) break;
    const auto found = scene.textures.find(slot.body.name);
    const std::optional<fs::path> texture = found == scene.textures.end() ? std::nullopt : std::optional(found->second);
    const ObjVertexOrder order(slot.body.surface);
    const std::uint64_t frame_bytes =
        ObjSequenceWriter::frameSizeBound(slot.body, order, texture, scene.render.bodies.at(slot.body.name), last);
    if (scene.write_obj) obj += frames * frame_bytes;
    if (scene.write_pc2) pc2 += Pc2Header::kSize + frames * order.size() * 12 + frame_bytes;  // and the base mesh
    std::error_code error;
    const std::uintmax_t texture_bytes = texture ? fs::file_size(*texture, error) : 0;
    if (!error) other += texture_bytes;
  }
  const std::string per = plural(bodies.size(), "body", "bodies") + " x " + plural(frames, "frame");
  if (obj > 0) e.parts.push_back({"OBJ + MTL, " + per, obj, {"no OBJ sequence (--set output.obj=false)"}});
  if (pc2 > 0) e.parts.push_back({"PC2, " + per, pc2, {"no point cache (no --pc2, output.pc2 = false)"}});
  addPictures(e, scene, e.frames, "no pictures (--render none)");
  other += carriedBytes(scene);  // the scene and its files, carried into OUT/scene (carried_scene.h)
  e.parts.push_back({"textures, the carried scene and run.json", other, {}});
  return e;
}

DiskEstimate estimateRenderOutput(const SceneFile& scene, int first, int last) {
  DiskEstimate e = framesOf(first, last, "--frames A:B");
  addPictures(e, scene, e.frames, "");
  return e;
}

std::uint64_t freeDiskSpace(const fs::path& path) {
  fs::path at = fs::absolute(path).lexically_normal();
  std::error_code error;
  while (!fs::exists(at, error) && at.has_parent_path() && at.parent_path() != at) at = at.parent_path();
  const fs::space_info space = fs::space(at, error);
  if (error)
    throw InputError(path.string() + ": cannot read the free space of its file system (" + at.string() +
                     "): " + error.message());
  return space.available;
}

void setDiskBudget(std::uint64_t bytes) { budget_override = bytes; }

std::optional<std::uint64_t> diskBudget() {
  return budget_override > 0 ? std::optional(budget_override) : std::nullopt;
}

void checkDiskBudget(const DiskEstimate& e, const fs::path& out) {
  const std::optional<std::uint64_t> max_disk = diskBudget();
  const std::uint64_t needed = e.bytes(), free = freeDiskSpace(out);
  const bool over_free = needed > free, over_max = max_disk && needed > *max_disk;
  if (!over_free && !over_max) return;
  std::string message = out.string() + ": this would write about " + e.describe() + ", ";
  if (over_max && (!over_free || *max_disk < free))
    message += "above --max-disk " + formatBytes(*max_disk) + " (" + formatBytes(free) + " free there)";
  else message += "above the " + formatBytes(free) + " free on its file system";
  message += ". To write less: " + e.fewer_frames;
  std::vector<std::string> said;
  for (const DiskEstimate::Part& p : e.parts)
    if (p.bytes * 10 >= needed)  // the parts that matter
      for (const std::string& change : p.changes)
        if (std::find(said.begin(), said.end(), change) == said.end()) {
          said.push_back(change);
          message += "; " + change;
        }
  throw InputError(message + ".");
}

}  // namespace wobble
