// A corpus of bad scene files, each run through the wobble binary: exit status 2, a message naming the file, the
// line and the key, and nothing written (the --out folder is never created). Sizes that would crash or exhaust
// memory, names that would write outside --out, non-finite and extreme numbers, nesting that would overflow the
// parser's stack (issue 8).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "image/image_file.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

struct BadScene {
  const char* name;
  std::string text;                   // the scene file (bad.toml)
  std::vector<std::string> expected;  // parts of the message: "bad.toml:LINE:", the key, the rule
  std::string extra_arguments = "";
};

const std::string kJelly = "[bodies.jelly]\ntype = \"jelly\"\nn = 3\n";  // lines 1-3

std::string deepHeader(int depth) {
  std::string h = "[a";
  for (int i = 0; i < depth; ++i) h += ".a";
  return h + "]\n";
}

// A PNG of a few bytes whose header declares width x height: stb reads only the IHDR chunk for the size.
std::string pngHeader(std::uint32_t width, std::uint32_t height) {
  std::string png = "\x89PNG\r\n\x1a\n";
  const auto be32 = [&](std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) png += char((v >> s) & 0xff);
  };
  be32(13);
  png += "IHDR";
  be32(width);
  be32(height);
  png += std::string("\x08\x00\x00\x00\x00", 5);  // 8-bit grey (RGBA would exceed stb's own 1 GB cap)
  be32(0);                                        // CRC (not checked for the size)
  return png;
}

// A Radiance HDR file's header declaring width x height, and a 2 x 1 run of pixels: stb reads the header for the size.
std::string hdrHeader(int width, int height) {
  return "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) + "\n" +
         std::string("\x80\x80\x80\x81\x80\x80\x80\x81", 8);
}

const BadScene kCorpus[] = {
    // Sizes (item 2): 32-bit wrap, bad_alloc, a silent 20 GB.
    {"JellyN2048",
     "[bodies.jelly]\ntype = \"jelly\"\nn = 2048\n",
     {"bad.toml:3:", "bodies.jelly.n = 2048", "[2, 894]"}},
    {"JellyN1000",
     "[bodies.jelly]\ntype = \"jelly\"\nn = 1000\n",
     {"bad.toml:3:", "bodies.jelly.n = 1000", "[2, 894]"}},
    {"JellyNMillion", "[bodies.jelly]\ntype = \"jelly\"\nn = 1000000\n", {"bad.toml:3:", "bodies.jelly.n = 1000000"}},
    {"JellyN300OverBudget",
     "[bodies.jelly]\ntype = \"jelly\"\nn = 300\n",
     {"bad.toml:3:", "bodies.jelly.n = 300", "27000000 particles", "memory budget of 1.0 GB", "--max-memory", "n <= "},
     "--max-memory 1GB"},
    {"ClothWrapsToZero",
     "[bodies.cloth]\ntype = \"cloth\"\nnx = 65536\nny = 65536\n",
     {"bad.toml:4:", "bodies.cloth.ny = 65536", "4294967296 particles", "32-bit"}},
    {"TwoBodiesOverBudget",
     kJelly + "[bodies.b]\ntype = \"jelly\"\nn = 100\n",
     {"bad.toml:6:", "bodies.b.n = 100", "memory budget of 100.0 MB"},
     "--max-memory 100MB"},
    // Names (item 3).
    {"NameEscapesOut",
     "[bodies.\"../../x\"]\ntype = \"jelly\"\nn = 3\n",
     {"bad.toml:1:", "bodies.\"../../x\"", "letters, digits"}},
    {"EmptyName", "[bodies.\"\"]\ntype = \"jelly\"\nn = 3\n", {"bad.toml:1:", "bodies.\"\"", "empty"}},
    {"NulInName", "[bodies.\"a\\u0000b\"]\ntype = \"jelly\"\nn = 3\n", {"bad.toml:1:", "bodies.\"a\\x00b\""}},
    {"LongColliderName",
     kJelly + "[colliders." + std::string(65, 'f') + "]\ntype = \"plane\"\n",
     {"bad.toml:4:", "colliders.\"fff", "65 characters"}},
    // Numbers (item 4).
    // Contact between bodies (issue 28): a jelly n = 3 of size 4 has springs of 2 m and longer.
    {"ThicknessZero", kJelly + "thickness = 0.0\n", {"bad.toml:4:", "bodies.jelly.thickness = 0", "> 0"}},
    {"ThicknessNegative", kJelly + "thickness = -0.1\n", {"bad.toml:4:", "bodies.jelly.thickness = -0.1", "> 0"}},
    {"ThicknessBeyondShortestSpring",
     kJelly + "thickness = 2.0\n",
     {"bad.toml:4:", "bodies.jelly.thickness = 2", "shortest spring, 2 m"}},
    {"FrictionNegative", kJelly + "friction = -0.5\n", {"bad.toml:4:", "bodies.jelly.friction = -0.5", ">= 0"}},
    {"ContactUnknownKey",
     "[contact]\nccd_iteration = 3\n" + kJelly,
     {"bad.toml:2:", "contact.ccd_iteration", "ccd_iterations"}},
    {"ContactInSolveNotBoolean",
     "[contact]\nin_solve = \"no\"\n" + kJelly,
     {"bad.toml:2:", "contact.in_solve", "true or false"}},
    {"ContactZoneIterationsZero",
     "[contact]\nzone_iterations = 0\n" + kJelly,
     {"bad.toml:2:", "contact.zone_iterations = 0", "[1, 10000]"}},
    {"NewtonToleranceZero",
     "[simulation]\nnewton_tolerance = 0\n" + kJelly,
     {"bad.toml:2:", "simulation.newton_tolerance = 0", "> 0"}},
    {"NewtonMaxIterationsTooMany",
     "[simulation]\nnewton_max_iterations = 5000\n" + kJelly,
     {"bad.toml:2:", "simulation.newton_max_iterations = 5000", "[1, 1000]"}},
    {"LineSearchUnknown",
     "[simulation]\nline_search = \"armijo\"\n" + kJelly,
     {"bad.toml:2:", "simulation.line_search = \"armijo\"", "potential, residual"}},
    {"LineSearchHalvingsNegative",
     "[simulation]\nline_search_halvings = -1\n" + kJelly,
     {"bad.toml:2:", "simulation.line_search_halvings = -1", "[0, 60]"}},
    {"ContactSplitStepsNegative",
     "[contact]\nsplit_steps = -1\n" + kJelly,
     {"bad.toml:2:", "contact.split_steps = -1", "[0, 20]"}},
    {"DtInf", "[simulation]\ndt = inf\n" + kJelly, {"bad.toml:2:", "simulation.dt = inf", "finite"}},
    {"FpsInf", "[simulation]\nfps = +inf\n" + kJelly, {"bad.toml:2:", "simulation.fps = inf", "finite"}},
    {"DurationNan", "[simulation]\nduration = nan\n" + kJelly, {"bad.toml:2:", "simulation.duration = nan", "finite"}},
    {"KsInf", kJelly + "ks = inf\n", {"bad.toml:4:", "bodies.jelly.ks = inf", "finite"}},
    {"MassInf", kJelly + "mass = inf\n", {"bad.toml:4:", "bodies.jelly.mass = inf", "finite"}},
    {"SizeInf", kJelly + "size = inf\n", {"bad.toml:4:", "bodies.jelly.size = inf", "finite"}},
    {"ClothSizeInf", "[bodies.c]\ntype = \"cloth\"\nsize = [1, inf]\n", {"bad.toml:3:", "bodies.c.size", "finite"}},
    {"CenterNan", kJelly + "center = [0, nan, 0]\n", {"bad.toml:4:", "bodies.jelly.center", "finite"}},
    {"RadiusInf",
     kJelly + "[colliders.ball]\ntype = \"sphere\"\nradius = inf\n",
     {"bad.toml:6:", "colliders.ball.radius = inf", "finite"}},
    {"IntegerBeyond2To53",
     kJelly + "ks = 9007199254740993\n",
     {"bad.toml:4:", "bodies.jelly.ks = 9007199254740993", "2^53"}},
    {"DtTooSmall",
     "[simulation]\ndt = 1e-300\n" + kJelly,
     {"bad.toml:2:", "simulation.dt = 1e-300", "steps per frame", "1000000"}},
    {"FpsTooHigh", "[simulation]\nfps = 1e9\n" + kJelly, {"bad.toml:2:", "simulation.fps", "100000 frames"}},
    {"DurationTooLong",
     "[simulation]\nduration = 1e7\n" + kJelly,
     {"bad.toml:2:", "simulation.duration", "100000 frames"}},
    {"RenderExposureInf", kJelly + "[render]\nexposure = -inf\n", {"bad.toml:5:", "render.exposure", "finite"}},
    // Nesting (item 5): toml++ would overflow its stack on these.
    {"DeepHeader", kJelly + deepHeader(50000), {"bad.toml:4:", "nesting too deep", "64"}},
    {"DeepArray",
     kJelly + "x = " + std::string(100000, '[') + std::string(100000, ']') + "\n",
     {"bad.toml:4:", "nesting too deep"}},
    {"DeepInlineTable",
     kJelly + "x = " +
         [] {
           std::string t;
           for (int i = 0; i < 100; ++i) t += "{a = ";
           return t + "1" + std::string(100, '}');
         }() +
         "\n",
     {"bad.toml:4:", "nesting too deep"}},
    {"DeepDottedKey",
     kJelly +
         [] {
           std::string k = "x";
           for (int i = 0; i < 80; ++i) k += ".x";
           return k + " = 1";
         }() +
         "\n",
     {"bad.toml:4:", "nesting too deep"}},
    {"DeepMultiLineArray",
     kJelly + "x = " +
         [] {
           std::string t;
           for (int i = 0; i < 100; ++i) t += "[\n";
           return t;
         }(),
     {"bad.toml:", "nesting too deep"}},
    // Gelatine and the lens (issue 29): each key's rule, where the reader knows the line.
    {"GelatineIorOne",
     kJelly + "material = \"gelatine\"\nior = 1.0\n",
     {"bad.toml:5:", "bodies.jelly.ior = 1", "(1, 4]"}},
    {"GelatineIorAbsurd",
     kJelly + "material = \"gelatine\"\nior = 4.5\n",
     {"bad.toml:5:", "bodies.jelly.ior = 4.5", "(1, 4]"}},
    {"GelatineScatterNegative",
     kJelly + "material = \"gelatine\"\nscatter = -0.5\n",
     {"bad.toml:5:", "bodies.jelly.scatter = -0.5", ">= 0"}},
    {"GelatineAbsorptionNegative",  // a colour above 1 would be light gained inside
     kJelly + "material = \"gelatine\"\nabsorption_color = [1.5, 0.5, 0.5]\n",
     {"bad.toml:5:", "bodies.jelly.absorption_color", "(0, 1]"}},
    {"GelatineAbsorptionDepthZero",
     kJelly + "material = \"gelatine\"\nabsorption_depth = 0\n",
     {"bad.toml:5:", "bodies.jelly.absorption_depth = 0", "> 0"}},
    {"GelatineScatterAlbedo",
     kJelly + "material = \"gelatine\"\nscatter_albedo = [0.5, -1, 0.5]\n",
     {"bad.toml:5:", "bodies.jelly.scatter_albedo", "[0, 1]"}},
    {"GelatinePrint",
     kJelly + "material = \"gelatine\"\nprint = 2\n",
     {"bad.toml:5:", "bodies.jelly.print = 2", "[0, 1]"}},
    {"GelatineOnACloth",
     "[bodies.sheet]\ntype = \"cloth\"\nmaterial = \"gelatine\"\n",
     {"bad.toml:3:", "bodies.sheet.material", "closed surface"}},
    {"IorWithoutGelatine", kJelly + "ior = 1.3\n", {"bad.toml:4:", "ior", "unknown"}},
    {"ApertureNegative", kJelly + "[camera]\naperture = -0.1\n", {"bad.toml:5:", "camera.aperture = -0.1", ">= 0"}},
    {"FocusZero", kJelly + "[camera]\nfocus = 0\n", {"bad.toml:5:", "camera.focus = 0", "> 0"}},
    {"ShutterAboveOne", kJelly + "[camera]\nshutter = 1.5\n", {"bad.toml:5:", "camera.shutter = 1.5", "[0, 1]"}},
    {"ShutterNegative", kJelly + "[camera]\nshutter = -0.5\n", {"bad.toml:5:", "camera.shutter = -0.5", "[0, 1]"}},
    {"FocusOnABodyNotFollowed",
     kJelly + "[camera]\nfocus = \"jelly\"\n",
     {"bad.toml:5:", "camera.focus", "camera.follow is not set"}},
    {"HugeFile", kJelly + "# " + std::string(2 << 20, 'x') + "\n", {"bad.toml", "bytes, above the limit"}},
};

class BadScenes : public testing::ScratchDir, public ::testing::WithParamInterface<BadScene> {};

std::string slurp(const fs::path& file) {
  std::ostringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

// Exit status of `wobble ARGS`, its output in log.
int runBinary(const std::string& arguments, const fs::path& log) {
  const int status =
      std::system((std::string(WOBBLE_BINARY) + " " + arguments + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void expectRefused(const fs::path& scene, const std::string& extra, const fs::path& out,
                   const std::vector<std::string>& expected) {
  const fs::path log = out.parent_path() / "log.txt";
  EXPECT_EQ(runBinary("run " + scene.string() + " --out " + out.string() + " " + extra, log), 2) << slurp(log);
  const std::string message = slurp(log);
  for (const std::string& part : expected)
    EXPECT_NE(message.find(part), std::string::npos) << part << " in " << message;
  EXPECT_FALSE(fs::exists(out)) << "written despite the error";
}

TEST_P(BadScenes, RefusedWithFileLineKeyAndNothingWritten) {
  expectRefused(write("bad.toml", GetParam().text), GetParam().extra_arguments, dir() / "out", GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadScenes, ::testing::ValuesIn(kCorpus),
                         [](const auto& info) { return std::string(info.param.name); });

class BadFiles : public testing::ScratchDir {};

TEST_F(BadFiles, TextureDeclaringAHugeSizeIsRefusedFromItsHeader) {
  std::ofstream(dir() / "huge.png", std::ios::binary) << pngHeader(20000, 20000);
  expectRefused(write("bad.toml", kJelly + "texture = \"huge.png\"\n"), "", dir() / "out",
                {"bad.toml:4:", "bodies.jelly.texture = \"huge.png\"", "20000 x 20000", "16384"});
  std::ofstream(dir() / "junk.png", std::ios::binary) << "not a png";
  expectRefused(write("bad.toml", kJelly + "texture = \"junk.png\"\n"), "", dir() / "out",
                {"bad.toml:4:", "bodies.jelly.texture", "cannot read the image"});
}

// render.environment: checked from the file's header when the scene is read, before anything is written.
TEST_F(BadFiles, EnvironmentMapThatIsMissingNotAnImageNot2To1OrTooLargeIsRefused) {
  const auto scene = [&](const std::string& file, const std::string& more = "") {
    return write("bad.toml", kJelly + "[render]\nenvironment = \"" + file + "\"\n" + more);  // line 5
  };
  const std::string allowed = "allowed: an equirectangular Radiance .hdr or OpenEXR .exr file";
  expectRefused(scene("nowhere.hdr"), "", dir() / "out",
                {"bad.toml:5:", "render.environment = \"nowhere.hdr\"", "file not found", allowed});
  std::ofstream(dir() / "junk.hdr", std::ios::binary) << "not an image";
  expectRefused(scene("junk.hdr"), "", dir() / "out",
                {"bad.toml:5:", "render.environment = \"junk.hdr\"", "not an image wobble reads", allowed});
  std::ofstream(dir() / "sky.png", std::ios::binary) << pngHeader(64, 32);
  expectRefused(scene("sky.png"), "", dir() / "out",
                {"bad.toml:5:", "render.environment", "PNG image of display values", allowed});
  std::ofstream(dir() / "narrow.hdr", std::ios::binary) << hdrHeader(30, 16);
  expectRefused(scene("narrow.hdr"), "", dir() / "out",
                {"bad.toml:5:", "render.environment = \"narrow.hdr\"", "30 x 16 pixels, not twice as wide as high"});
  std::ofstream(dir() / "huge.hdr", std::ios::binary) << hdrHeader(18000, 9000);
  expectRefused(scene("huge.hdr"), "", dir() / "out",
                {"bad.toml:5:", "render.environment = \"huge.hdr\"", "18000 x 9000 pixels", "16384 x 8192"});
  std::ofstream(dir() / "small.hdr", std::ios::binary) << hdrHeader(2, 1);
  expectRefused(scene("small.hdr", "environment_strength = -1\n"), "", dir() / "out",
                {"bad.toml:6:", "render.environment_strength = -1", ">= 0"});
  expectRefused(write("bad.toml", kJelly + "[render]\nenvironment_rotation = 90\n"), "", dir() / "out",
                {"bad.toml:5:", "render.environment_rotation = 90", "set render.environment"});
  // A cut OpenEXR file: refused when its header or its pixels fail to read, before any file is written.
  image::writeExrImage(dir() / "whole.exr", image::ImageF(64, 32, 3), {"R", "G", "B"}, true);
  std::string exr = slurp(dir() / "whole.exr");
  std::ofstream(dir() / "cut.exr", std::ios::binary) << exr.substr(0, exr.size() / 2);
  expectRefused(scene("cut.exr"), "--frames 1 --resolution 8x8", dir() / "out", {"cut.exr", "render.environment"});
}

// Every image read checks its header first: `wobble diff` of such a file is exit 4 (a file cannot be read, as idiff).
TEST_F(BadFiles, DiffRefusesAHugeImageFromItsHeader) {
  const fs::path huge = dir() / "huge.png";
  std::ofstream(huge, std::ios::binary) << pngHeader(20000, 20000);
  EXPECT_EQ(runBinary("diff " + huge.string() + " " + huge.string(), dir() / "log.txt"), 4);
  EXPECT_NE(slurp(dir() / "log.txt").find("20000 x 20000 pixels; at most 16384"), std::string::npos);
}

TEST_F(BadFiles, SceneNameMustBeAnIdentifier) {
  expectRefused(write("bad.name.toml", kJelly), "", dir() / "out",
                {"bad.name.toml", "scene name \"bad.name\"", "letters, digits"});
}

TEST_F(BadFiles, OverridesAreCheckedToo) {
  const fs::path scene = write("ok.toml", kJelly);
  expectRefused(scene, "--set jelly.n=2048", dir() / "out", {"bodies.jelly.n = 2048", "(--set)"});
  expectRefused(scene, "--set jelly.ks=inf", dir() / "out", {"bodies.jelly.ks = inf", "finite"});
  expectRefused(scene, "--dt 1e-300", dir() / "out", {"simulation.dt", "steps per frame"});
  expectRefused(scene, "--set 'x=" + std::string(1000, '[') + "'", dir() / "out", {"--set x=", "nesting too deep"});
}

// A scale that takes a model beyond any finite lattice (the fuzzer's jelly_mould with scale = 1e308 once stopped deep
// in the model's weights, exit 1): a scene error naming the file, line, key, value and the largest scale allowed, for
// the mesh jelly and for the mesh collider alike.
TEST_F(BadFiles, MeshScaleThatOverflowsIsRefused) {
  const fs::path models = fs::path(WOBBLE_SOURCE_DIR) / "scenes" / "models";
  const fs::path scene =
      write("mould.toml", "[bodies.jelly]\ntype = \"jelly\"\nmesh = \"" + (models / "jelly_mould.obj").string() +
                              "\"\ncells = 3\nscale = 1e308\n");
  expectRefused(scene, "", dir() / "out",
                {"mould.toml:5:", "bodies.jelly.scale = 1e+308", "2.14 m across", "allowed: at most 1e+06 m",
                 "scale <= 4.673e+05"});
  const fs::path mould = fs::path(WOBBLE_SOURCE_DIR) / "scenes" / "jelly_mould.toml";
  expectRefused(mould, "--set jelly.scale=1e7", dir() / "out",
                {"(--set)", "bodies.jelly.scale = 10000000", "scale <= "});
  expectRefused(mould, "--set plate.scale=1e300", dir() / "out",
                {"colliders.plate.scale = 1", "4.8e+300 m", "scale <= 2.083e+05"});
}

TEST_F(BadFiles, MaxMemoryOption) {
  const fs::path scene = write("ok.toml", kJelly + "[output]\nobj = false\n[render]\npng = false\n");
  expectRefused(scene, "--max-memory 1KB", dir() / "out", {"ok.toml:3:", "bodies.jelly.n = 3", "1.0 KB"});
  expectRefused(scene, "--max-memory lots", dir() / "out", {"--max-memory"});
  EXPECT_EQ(runBinary("run " + scene.string() + " --max-memory 64MB --out " + (dir() / "good").string(),
                      dir() / "log.txt"),
            0)
      << slurp(dir() / "log.txt");
}

// A 16384 x 16384 frame's buffers (film, denoiser, the frame being written) are 128 GB: over any default budget
// here, refused before the simulation starts; with no images the same resolution costs nothing.
TEST_F(BadFiles, RenderBuffersCountInTheBudget) {
  const fs::path scene = write("ok.toml", kJelly + "[render]\npng = true\n");
  expectRefused(scene, "--resolution 16384x16384 --max-memory 8GB", dir() / "out",
                {"camera.resolution = [ 16384, 16384 ]", "268435456 image pixels", "8.0 GB"});
  EXPECT_EQ(runBinary("run " + scene.string() + " --render none --resolution 16384x16384 --max-memory 8GB --out " +
                          (dir() / "good").string(),
                      dir() / "log.txt"),
            0)
      << slurp(dir() / "log.txt");
}

}  // namespace
}  // namespace wobble
