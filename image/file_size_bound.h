// The most bytes the picture writers write for a picture of a given size, whatever its pixels: what a command that
// will write many frames can promise before it renders any (app/output/disk_budget.h). Pictures compress to less, by
// how much depends on what they show; no tighter bound exists before rendering.
//   pngSizeBound  writePng (png_io.h): the image data as deflate's worst case (stored blocks, a little above the
//                 uncompressed size: libdeflate_zlib_compress_bound) and every chunk, text chunks included
//   exrSizeBound  writeExr (exr_writer.h): every channel uncompressed (OpenEXR stores a 16-line block raw when ZIP
//                 does not make it smaller), each block's offset and header, the header with its attributes
#pragma once
#include <cstdint>
#include <map>
#include <string>

namespace wobble::image {

std::uint64_t pngSizeBound(int width, int height, int channels, const std::map<std::string, std::string>& text = {});
// denoised: the film is written with a denoised colour (three more channels).
std::uint64_t exrSizeBound(int width, int height, bool denoised, const std::map<std::string, std::string>& text = {});

}  // namespace wobble::image
