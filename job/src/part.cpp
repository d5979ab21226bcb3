// A part's faces as a selection of its triangles (part.hpp).
#include "millnet/job/part.hpp"

namespace millnet::job {

std::vector<bool> triangles_of_faces(const std::vector<std::int32_t>& triangle_face,
                                     const std::vector<bool>& chosen_face) {
  std::vector<bool> out(triangle_face.size(), false);
  for (std::size_t t = 0; t < triangle_face.size(); ++t) {  // O(triangles)
    const auto f = static_cast<std::size_t>(triangle_face[t]);
    out[t] = f < chosen_face.size() && chosen_face[f];
  }
  return out;
}

}  // namespace millnet::job
