// GridLayout: how `wobble compare` lays its variants' tiles out in one picture. The grid fits in the size a run's
// frame would have (the scene's camera.resolution after --resolution and --quality), and each tile keeps that
// aspect, so a tile is the run's view, smaller, rendered at its own size (not rendered large and shrunk).
// Two --vary give the rows (the first) and the columns (the second); one --vary of n values takes the arrangement
// with the largest tiles (the most square: 2 -> 1 x 2, 3 and 4 -> 2 x 2, 5 and 6 -> 2 x 3), then the fewest empty
// cells, then the widest. Tile sizes are even, so the picture's are too (the video's yuv420p needs it).
#pragma once

namespace wobble {

struct GridLayout {
  int rows = 1, cols = 1;
  int tile_width = 0, tile_height = 0;

  int width() const { return cols * tile_width; }
  int height() const { return rows * tile_height; }
  // Top-left corner of tile `index`, row by row.
  int tileX(int index) const { return index % cols * tile_width; }
  int tileY(int index) const { return index / cols * tile_height; }
};

// rows x cols tiles in a box of box_width x box_height pixels. Throws std::invalid_argument unless all are >= 1
// and a tile gets at least 2 x 2 pixels.
GridLayout gridLayout(int rows, int cols, int box_width, int box_height);
// count tiles (>= 1) in the arrangement described above.
GridLayout gridLayout(int count, int box_width, int box_height);

}  // namespace wobble
