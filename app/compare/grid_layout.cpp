#include "app/compare/grid_layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace wobble {

GridLayout gridLayout(int rows, int cols, int box_width, int box_height) {
  if (rows < 1 || cols < 1 || box_width < 1 || box_height < 1)
    throw std::invalid_argument("gridLayout: rows, cols and the box must be >= 1");
  GridLayout g{rows, cols};
  // With the box's aspect, the tiles fill its width when there are at least as many columns as rows, else its
  // height; the other side follows from the aspect, to the nearest even size that still fits.
  const auto evenFloor = [](int n) { return n - n % 2; };
  const auto evenNearest = [](double x) { return 2 * int(std::lround(x / 2)); };
  if (cols >= rows) {
    g.tile_width = evenFloor(box_width / cols);
    g.tile_height = std::min(evenNearest(double(g.tile_width) * box_height / box_width), evenFloor(box_height / rows));
  } else {
    g.tile_height = evenFloor(box_height / rows);
    g.tile_width = std::min(evenNearest(double(g.tile_height) * box_width / box_height), evenFloor(box_width / cols));
  }
  if (g.tile_width < 2 || g.tile_height < 2)
    throw std::invalid_argument("gridLayout: " + std::to_string(rows) + " x " + std::to_string(cols) +
                                " tiles do not fit in " + std::to_string(box_width) + " x " +
                                std::to_string(box_height) + " pixels");
  return g;
}

GridLayout gridLayout(int count, int box_width, int box_height) {
  if (count < 1) throw std::invalid_argument("gridLayout: count must be >= 1");
  int best_cols = 1;
  const auto rowsFor = [count](int cols) { return (count + cols - 1) / cols; };
  const auto side = [&](int cols) { return std::max(cols, rowsFor(cols)); };  // tiles shrink with the longer side
  for (int cols = 2; cols <= count; ++cols) {
    const int cells = cols * rowsFor(cols), best_cells = best_cols * rowsFor(best_cols);
    if (side(cols) < side(best_cols) || (side(cols) == side(best_cols) && cells <= best_cells)) best_cols = cols;
  }
  return gridLayout(rowsFor(best_cols), best_cols, box_width, box_height);
}

}  // namespace wobble
