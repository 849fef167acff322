// yeeFailures: idiff -p, Yee's perceptual metric (H. Yee, "A perceptual metric for production testing", Journal of
// Graphics Tools 9(4), 2004) exactly as OpenImageIO 2.4 computes it (ImageBufAlgo::compare_Yee with idiff's
// parameters: adaptation luminance 100 cd/m^2, field of view 45 degrees), so that `wobble diff -p` fails the pairs
// idiff -p fails.
//
// What 2.4 computes: both images (the first three channels, over the union of their extents, missing values 0) go
// from Adobe RGB (1998) through XYZ to CIE L*a*b*. The metric's luminance test reads a Gaussian pyramid of Y through
// channel 1 of one-channel images, which reads as 0 at every level: every contrast is 0, the adaptation luminance is
// clamped to 1e-5, so the luminance test never fails, the threshold factor is clamped to its minimum 1 and the colour
// test runs with the scotopic colour scale 0.01. A pixel therefore fails when 0.01 * (da*^2 + db*^2) > 1: a chroma
// difference over 10 a*b* units. Brightness differences alone never fail it (black against white passes; the real
// idiff 2.4 agrees, tests/app/idiff_conformance_test.cpp). We compute that, and say so, rather than Yee's full metric,
// whose decisions would differ from the idiff the tests hold us to.
// Returns the number of failing pixels.
#pragma once
#include "image/image.h"

namespace wobble::image {

long yeeFailures(const ImageF& a, const ImageF& b);

}  // namespace wobble::image
