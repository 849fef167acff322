// readImageFile: any image wobble writes or reads, as floats, for comparisons (`wobble diff`):
//   EXR   half or float channels, linear values; by default the channels of the unnamed layer (R, G, B, A first, then
//         the rest in the file's order: what a wobble frame shows), or those a ChannelChoice names
//   HDR   Radiance RGBE, linear values (stb_image decodes RGBE exactly as OpenImageIO does: mantissa * 2^(e - 136))
//   PFM   "PF" (RGB) or "Pf" (grey), either byte order, rows stored bottom to top
//   PNG   8-bit (codes * 1/255) or 16-bit (codes / 65535), the stored values: no colour decoding, as idiff reads them;
//         with alpha, the colour premultiplied by it as OpenImageIO does (on the codes; with the file's gAMA if any);
//         other 8-bit formats stb_image reads (JPEG, BMP, TGA) as stored
// Channel names follow OpenImageIO: Y; Y, A; R, G, B; R, G, B, A for the formats without names.
// Every file's size is read from its header first: more than kMaxImageSide on a side is refused before anything is
// decoded. Errors throw ImageFileError naming the file and the reason (not an image, truncated, empty, too large, no
// such channel or layer).
//
// ChannelChoice (EXR; on other formats only names the format has, and no layer):
//   layer     "albedo": the channels albedo.*, R, G, B, A first
//   channels  "noisy.R,G,B" -> noisy.R, noisy.G, noisy.B: an item without a layer takes the --layer, or else the
//             layer of the item before it; "R,G,B" in a file with layers: the unnamed layer's
//
// writeExrImage writes an ImageF as a scanline EXR (ZIP), half or float, atomically (tests, and HDR outputs).
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/image.h"

namespace wobble::image {

struct ImageFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ChannelChoice {
  std::string layer;
  std::vector<std::string> channels;  // as given: items without a layer are resolved as above
  bool empty() const { return layer.empty() && channels.empty(); }
};

// "noisy.R,G,B" -> {"noisy.R", "G", "B"} (resolution against a file happens in readImageFile).
std::vector<std::string> splitChannelList(const std::string& list);

struct ImageFile {
  ImageF image;
  std::vector<std::string> channels;  // one name per channel of image
  bool linear = false;                // scene-referred values (EXR, HDR, PFM), not display values in [0, 1]
  std::string format;                 // "EXR", "HDR", "PFM", "PNG", ...
};

ImageFile readImageFile(const std::filesystem::path& file, const ChannelChoice& choice = {});

// How many images the file holds in idiff -a's sense (subimages and MIP levels): an EXR's parts, a tiled part's
// levels counted; 1 for every other format (and for a file that cannot be read: readImageFile says why).
int subimageCount(const std::filesystem::path& file);

void writeExrImage(const std::filesystem::path& file, const ImageF& image, const std::vector<std::string>& channels,
                   bool half);

}  // namespace wobble::image
