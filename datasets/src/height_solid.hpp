#pragma once
// Internal: the closed height-field solid every generated part is built as (generator.hpp's mesh layout).
#include "millnet/datasets/generator.hpp"

#include <functional>

namespace millnet::datasets::detail {

using HeightFn = std::function<double(double, double)>;

/// Closed height-field solid over [0,a]×[0,b]: top grid (res_x × res_y vertices, row-major, row = y), a
/// ring of bottom vertices under the top's boundary, vertical sides, a bottom fan at z = 0; outward
/// normals. The top is shifted so that its lowest point is at z = plinth. O(res_x·res_y).
[[nodiscard]] GeneratedMesh height_field_solid(double a, double b, int res_x, int res_y, double plinth,
                                               const HeightFn& f);

}  // namespace millnet::datasets::detail
