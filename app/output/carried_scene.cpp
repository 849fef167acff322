#include "app/output/carried_scene.h"

#include <map>
#include <sstream>
#include <system_error>

#include <toml++/toml.h>

#include "app/scene/input_error.h"
#include "app/scene/table_reader.h"
#include "io/atomic_file.h"
#include "io/content_hash.h"
#include "io/text_file.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

std::string fileHash(const fs::path& file) {
  io::ContentHash h;
  h.addFile(file);
  return h.hex();
}

// "files/<16 hex digits>/<name>": relative to the carried scene file.
std::string carriedName(const std::string& hash, const fs::path& file) {
  return "files/" + hash.substr(0, 16) + "/" + file.filename().string();
}

// The scene text with each file key pointing at its carried copy.
std::string carriedText(const SceneFile& scene, const std::map<fs::path, std::string>& names) {
  const toml::table table = withFileValues(toml::parse(scene.text, scene.file.string()), scene.files,
                                           [&](const SceneFileUse& use) { return names.at(use.path); });
  std::ostringstream text;
  text << "# " << scene.name << " as run: " << scene.file.string()
       << " after --set and the flags, its files carried beside it (wobble run)\n"
       << table << "\n";
  return text.str();
}

}  // namespace

std::vector<CarriedFile> carryScene(const SceneFile& scene, const fs::path& out) {
  const fs::path folder = out / "scene";
  std::map<fs::path, std::string> names;  // source -> carried name, relative to the scene copy
  std::vector<CarriedFile> carried(1);
  for (const SceneFileUse& use : scene.files) {
    if (names.count(use.path)) continue;
    const std::string hash = fileHash(use.path), name = carriedName(hash, use.path);
    names[use.path] = name;
    const fs::path to = folder / name;
    fs::create_directories(to.parent_path());
    if (!fs::exists(to) || fileHash(to) != hash) io::writeFileAtomically(to, io::readTextFile(use.path));
    carried.push_back({"scene/" + name, hash, use.path.string()});
  }
  // An earlier run's files that this scene no longer uses go.
  std::error_code ignored;
  if (fs::is_directory(folder / "files"))
    for (const auto& entry : fs::directory_iterator(folder / "files")) {
      bool used = false;
      for (const CarriedFile& c : carried)
        used = used || c.path.starts_with("scene/files/" + entry.path().filename().string() + "/");
      if (!used) fs::remove_all(entry.path(), ignored);
    }
  const std::string text = carriedText(scene, names);
  const fs::path copy = folder / (scene.name + ".toml");
  fs::create_directories(folder);
  io::writeFileAtomically(copy, text);
  carried[0] = {"scene/" + copy.filename().string(), fileHash(copy), scene.file.string()};
  return carried;
}

void checkCarriedFiles(const fs::path& out, const std::vector<CarriedFile>& files) {
  for (const CarriedFile& c : files) {
    const fs::path file = out / c.path;
    if (!fs::is_regular_file(file))
      throw InputError(file.string() +
                       ": missing: the run carried it (run.json, carried) and reads it back; the "
                       "folder is incomplete (copy it whole, or run the scene again)");
    const std::string hash = fileHash(file);
    if (hash != c.hash)
      throw InputError(file.string() + ": altered since the run (content hash " + hash.substr(0, 16) +
                       ", run.json has " + c.hash.substr(0, 16) +
                       "): pictures from it would not be the run's; restore it, or run the scene again");
  }
}

std::uintmax_t carriedBytes(const SceneFile& scene) {
  std::uintmax_t bytes = scene.text.size() + 200;
  std::error_code error;
  std::map<fs::path, bool> seen;
  for (const SceneFileUse& use : scene.files)
    if (!seen[use.path]) {
      seen[use.path] = true;
      const std::uintmax_t size = fs::file_size(use.path, error);
      if (!error) bytes += size;
    }
  return bytes;
}

}  // namespace wobble
