// A part's faces as a selection of its triangles (part.hpp).
#include "millnet/job/part.hpp"

#include "millnet/core/error.hpp"

#include <algorithm>

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

std::vector<bool> face_selection(const job::Part& part, const std::vector<std::string>& faces) {
  const std::string file = part.file.string();
  if (!part.cad)
    throw Error(file +
                ": --faces / /finish/boundary/faces select faces of a STEP or IGES part; this part is a mesh "
                "without faces (use --boundary FILE or --z-range)");
  const ingest::CadReport& cad = *part.cad;
  std::vector<bool> chosen_face(cad.faces + 1, false);
  for (const std::string& f : faces) {
    const bool digits =
        !f.empty() && f.size() < 10 && std::all_of(f.begin(), f.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits) {
      const std::size_t k = std::stoul(f);
      if (k < 1 || k > cad.faces)
        throw Error(file + ": no face " + f + " (--faces / /finish/boundary/faces: the part has " +
                    std::to_string(cad.faces) + " faces, 1–" + std::to_string(cad.faces) + ")");
      chosen_face[k] = true;
      continue;
    }
    bool found = false;
    for (std::size_t k = 0; k < cad.face_names.size(); ++k)  // O(faces)
      if (cad.face_names[k] == f) chosen_face[k + 1] = found = true;
    if (!found) {
      std::string named;
      std::size_t n = 0;
      for (const std::string& name : cad.face_names)
        if (!name.empty() && n < 8 && named.find("\"" + name + "\"") == std::string::npos)
          named += (n++ ? ", \"" : "\"") + name + "\"";
      throw Error(file + ": no face named \"" + f + "\" (--faces / /finish/boundary/faces; " +
                  (named.empty()
                       ? "no face of this part has a name: give 1-based indices, 1–" + std::to_string(cad.faces)
                       : "named faces: " + named + (n == 8 ? ", …" : "")) +
                  ")");
    }
  }
  return triangles_of_faces(cad.triangle_face, chosen_face);
}

}  // namespace millnet::job
