// The only file that sees assimp (ARCHITECTURE.md: heavy dependencies stay private at the edge).
// One owner per format: STL (binary and ASCII), PLY, OFF and point clouds are read by millnet (the
// text ones and PLY in ply_off.cpp), OBJ, 3MF and glTF by assimp, always with aiProcess_ValidateDataStructure.
#include "millnet/ingest/io/mesh_io.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/pointcloud.hpp"
#include "cad.hpp"
#include "ply_off.hpp"
#include "weld_key.hpp"

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <unordered_map>

namespace millnet::ingest {

namespace fs = std::filesystem;
static_assert(std::endian::native == std::endian::little, "STL I/O assumes a little-endian host");

namespace {

std::string lower_ext(const fs::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// Binary STL parsed directly: assimp decides ASCII vs binary from the "solid" prefix, which many
// exporters write into binary headers too. Identical vertices (bit-equal floats) are joined.
// O(#F) expected (hash map).
Mesh parse_stl_binary(const std::string& bytes, const std::string& name, MeshReport* report) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  using Key = detail::WeldKey<std::uint32_t>;
  detail::WeldIndex<std::uint32_t> index;
  index.reserve(static_cast<std::size_t>(n) / 2 + 16);
  std::vector<float> verts;
  verts.reserve(static_cast<std::size_t>(n) * 3 / 2 + 16);
  Mesh m;
  m.F.resize(static_cast<Eigen::Index>(n), 3);
  std::size_t zero_normals = 0;
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + 50 * static_cast<std::size_t>(t);
    float nrm[3];
    std::memcpy(nrm, rec, 12);
    if (nrm[0] == 0.0f && nrm[1] == 0.0f && nrm[2] == 0.0f) ++zero_normals;
    for (int k = 0; k < 3; ++k) {
      Key key{};
      std::memcpy(&key, rec + 12 + 12 * k, 12);
      const auto [it, inserted] = index.try_emplace(key, static_cast<std::int32_t>(verts.size() / 3));
      if (inserted) {
        float xyz[3];
        std::memcpy(xyz, &key, 12);
        verts.insert(verts.end(), xyz, xyz + 3);
      }
      m.F(static_cast<Eigen::Index>(t), k) = it->second;
    }
  }
  m.V.resize(static_cast<Eigen::Index>(verts.size() / 3), 3);
  for (std::size_t i = 0; i < verts.size(); ++i)
    m.V(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = static_cast<double>(verts[i]);
  if (report) {
    if (zero_normals)
      report->notes.push_back(std::to_string(zero_normals) +
                              " stored facet normals are zero (ignored: normals come from the winding)");
    report->notes.push_back("binary STL: stored normals ignored");
  }
  (void)name;
  return m;
}

// "x y z" per line (separators: blanks, ',' or ';'; extra columns ignored; '#' and '//' lines are
// comments). O(file size).
Mesh load_point_cloud(const fs::path& path, MeshReport* report) {
  const std::string name = path.string();
  const std::string text = read_file(path);
  std::vector<double> xyz;
  long line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    std::size_t b = 0;
    while (b < line.size() && std::isspace(static_cast<unsigned char>(line[b]))) ++b;
    line.remove_prefix(b);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.remove_suffix(1);
    if (line.empty() || line[0] == '#' || line.substr(0, 2) == "//") continue;
    double v[3];
    const char* p = line.data();
    const char* e = line.data() + line.size();
    for (int k = 0; k < 3; ++k) {
      while (p < e && (std::isspace(static_cast<unsigned char>(*p)) || *p == ',' || *p == ';')) ++p;
      if (p < e && *p == '+') ++p;
      const auto r = std::from_chars(p, e, v[k]);
      if (r.ec != std::errc())
        throw line_error(name, line_no,
                         "expected three numbers \"x y z\", got \"" + std::string(line.substr(0, 80)) + "\"");
      if (!std::isfinite(v[k])) throw line_error(name, line_no, "non-finite coordinate (NaN or inf)");
      p = r.ptr;
    }
    xyz.insert(xyz.end(), v, v + 3);
  }
  if (xyz.empty()) throw file_error(name, "no points (expected lines \"x y z\")");
  Vertices pts(static_cast<Eigen::Index>(xyz.size() / 3), 3);
  for (std::size_t i = 0; i < xyz.size(); ++i)
    pts(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = xyz[i];
  Mesh m = triangulate_height_field(pts, name);
  if (report)
    report->notes.push_back("point cloud of " + std::to_string(pts.rows()) +
                            " points triangulated as a height field over XY");
  return m;
}

void append_node(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, std::vector<double>& V,
                 std::vector<std::int32_t>& F, std::size_t& skipped) {
  const aiMatrix4x4 T = parent * node->mTransformation;
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
    const auto base = static_cast<std::int32_t>(V.size() / 3);
    // O(#V + #F) per mesh instance.
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      const aiVector3D p = T * mesh->mVertices[i];
      V.push_back(static_cast<double>(p.x));
      V.push_back(static_cast<double>(p.y));
      V.push_back(static_cast<double>(p.z));
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) {  // points and lines carry no surface
        ++skipped;
        continue;
      }
      for (unsigned j = 0; j < 3; ++j) F.push_back(base + static_cast<std::int32_t>(face.mIndices[j]));
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) append_node(scene, node->mChildren[c], T, V, F, skipped);
}

Mesh load_with_assimp(const fs::path& path, MeshReport* report) {
  const std::string name = path.string();
  Assimp::Importer importer;
  const std::string ext = lower_ext(path);
  if (!ext.empty() && !importer.IsExtensionSupported(ext)) {
    std::string list;
    importer.GetExtensionList(list);
    throw file_error(
        name, "unknown mesh format '" + ext + "' (readable: " + list + ", and point clouds .xyz .pts .txt .asc)");
  }
  // Validation first: assimp's later steps index vertices through the faces unchecked, so a face index
  // out of range corrupted the heap (tests/corpus/mesh/ply_face_index_out_of_range.ply).
  const aiScene* scene = importer.ReadFile(
      name, aiProcess_ValidateDataStructure | aiProcess_JoinIdenticalVertices | aiProcess_Triangulate);
  if (!scene || !scene->mRootNode) {
    // assimp's message may quote the rest of the file (a 5 KB line of an ASCII STL, issue 15): one
    // line, at most 160 characters of it (tests/corpus/mesh/obj_long_garbage_line.obj).
    std::string why = importer.GetErrorString();
    for (char& c : why)
      if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (why.size() > 160) why = why.substr(0, 157) + "...";
    throw file_error(name, "cannot read mesh: " + why);
  }
  std::vector<double> V;
  std::vector<std::int32_t> F;
  std::size_t skipped = 0;
  append_node(scene, scene->mRootNode, aiMatrix4x4(), V, F, skipped);
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(V.size() / 3), 3);
  for (std::size_t i = 0; i < V.size(); ++i)
    m.V(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = V[i];
  m.F.resize(static_cast<Eigen::Index>(F.size() / 3), 3);
  for (std::size_t i = 0; i < F.size(); ++i)
    m.F(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = F[i];
  if (report) {
    if (skipped) report->notes.push_back(std::to_string(skipped) + " point/line primitives skipped");
    report->notes.push_back("stored normals ignored");
  }
  return m;
}

}  // namespace

namespace {

Mesh read_stl(const fs::path& path, const CadOptions&, MeshReport* report) {
  const std::string name = path.string();
  const std::string bytes = read_file(path);
  std::uint32_t n = 0;
  if (bytes.size() >= 84) std::memcpy(&n, bytes.data() + 80, 4);
  const bool binary = bytes.size() >= 84 && bytes.size() == 84 + 50 * static_cast<std::uint64_t>(n);
  std::size_t b = 0;
  while (b < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[b]))) ++b;
  std::string head = bytes.substr(b, 5);
  for (char& c : head) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (binary) {
    if (head == "solid" && report)
      report->notes.push_back("binary STL whose header starts with 'solid' (read as binary: size = 84 + 50·n)");
    return parse_stl_binary(bytes, name, report);
  }
  if (head == "solid") {
    Mesh m = detail::parse_stl_ascii(bytes, name);
    if (report) report->notes.push_back("ASCII STL: stored normals ignored");
    return m;
  }
  throw file_error(name, "not an STL file: neither binary (" + std::to_string(bytes.size()) +
                             " bytes, expected 84 + 50·n) nor ASCII (does not start with 'solid')");
}

// Our own PLY and OFF readers: assimp's aborted, crashed, hung or clamped indices on malformed
// files (tests/corpus/mesh/ply_*, off_*).
Mesh read_ply(const fs::path& path, const CadOptions&, MeshReport* report) {
  Mesh m = detail::parse_ply(read_file(path), path.string());
  if (report) report->notes.push_back("polygons triangulated as fans; stored normals and colours ignored");
  return m;
}

Mesh read_off(const fs::path& path, const CadOptions&, MeshReport* report) {
  Mesh m = detail::parse_off(read_file(path), path.string());
  if (report) report->notes.push_back("polygons triangulated as fans; stored normals and colours ignored");
  return m;
}

Mesh read_cloud(const fs::path& path, const CadOptions&, MeshReport* report) { return load_point_cloud(path, report); }

Mesh read_with_assimp(const fs::path& path, const CadOptions&, MeshReport* report) {
  return load_with_assimp(path, report);
}

Mesh read_cad(const fs::path& path, const CadOptions& cad, MeshReport* report) {
  return detail::load_cad(path, cad, report);
}

std::vector<std::string> extensions_of(MeshFormatKind kind) {
  std::vector<std::string> ext;
  for (const MeshFormat& f : mesh_formats())
    if (f.kind == kind) ext.insert(ext.end(), f.extensions.begin(), f.extensions.end());
  return ext;
}

}  // namespace

const std::vector<MeshFormat>& mesh_formats() {
  static const std::vector<MeshFormat> formats{
      {"STL", MeshFormatKind::Mesh, {".stl"}, read_stl},
      {"OBJ, 3MF, glTF (assimp)", MeshFormatKind::Mesh, {".obj", ".3mf", ".gltf", ".glb"}, read_with_assimp},
      {"PLY", MeshFormatKind::Mesh, {".ply"}, read_ply},
      {"OFF", MeshFormatKind::Mesh, {".off"}, read_off},
      {"point cloud (x y z text)", MeshFormatKind::PointCloud, {".xyz", ".pts", ".txt", ".asc"}, read_cloud},
      {"STEP, IGES (Open CASCADE)", MeshFormatKind::Cad, detail::cad_extensions(), read_cad},
  };
  return formats;
}

const std::vector<std::string>& point_cloud_extensions() {
  static const std::vector<std::string> ext = extensions_of(MeshFormatKind::PointCloud);
  return ext;
}

const std::vector<std::string>& mesh_extensions() {
  static const std::vector<std::string> ext = [] {
    std::vector<std::string> all;
    for (const MeshFormat& f : mesh_formats()) all.insert(all.end(), f.extensions.begin(), f.extensions.end());
    return all;
  }();
  return ext;
}

Mesh load_prepared(const fs::path& path, const PrepareOptions& options, MeshReport* report) {
  MeshReport local;
  MeshReport* rep = report != nullptr ? report : &local;
  Mesh raw = load_mesh(path, options.cad, rep);
  if (!rep->is_cad) return prepare(raw, options, rep);
  // A CAD file was read in mm from its own unit; an explicit --units reinterprets its numbers.
  PrepareOptions o = options;
  o.units = Units::mm;
  CadReport& cad = rep->cad;
  if (options.units_explicit) {
    const double factor = units_to_mm(options.units) / cad.file_unit_mm;
    if (factor != 1.0) {
      raw.V *= factor;
      cad.units_overridden = !cad.file_unit.empty();
      const std::string asked = options.units == Units::mm ? "mm" : options.units == Units::inch ? "inch" : "m";
      cad.units_note = path.string() + ": the file states " +
                       (cad.file_unit.empty() ? "no unit" : "unit " + cad.file_unit) + ", read as " + asked +
                       " as asked (--units / config units)";
      rep->notes.push_back(cad.units_note);
    }
  }
  return prepare(raw, o, rep);
}

Mesh load_mesh(const fs::path& path, MeshReport* report) { return load_mesh(path, CadOptions{}, report); }

bool cad_supported() { return detail::cad_supported(); }

Mesh load_mesh(const fs::path& path, const CadOptions& cad, MeshReport* report) {
  const std::string name = path.string();
  std::error_code ec;
  if (!fs::exists(path, ec)) throw file_error(name, "no such file");
  if (fs::is_directory(path, ec)) throw file_error(name, "is a folder, expected a mesh file");
  // Refused before anything opens it: a FIFO blocks the open, /dev/zero behind x.stl never ends.
  if (!fs::is_regular_file(path, ec))
    throw file_error(name, "not a regular file (a device, FIFO or socket), expected a mesh file");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw file_error(name, "cannot open for reading");
  }
  // A file whose extension no format lists goes to assimp, which knows more formats than it is listed for.
  const std::string ext = lower_ext(path);
  Mesh (*read)(const fs::path&, const CadOptions&, MeshReport*) = read_with_assimp;
  for (const MeshFormat& f : mesh_formats())
    if (std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end()) read = f.read;
  Mesh m = read(path, cad, report);
  validate(m, name, report);
  return m;
}

void save_stl_binary(const Mesh& mesh, const fs::path& path, std::string_view header) {
  validate(mesh, path.string());
  const auto nf = static_cast<std::size_t>(mesh.F.rows());
  if (nf > 0xFFFFFFFFull) throw file_error(path.string(), "too many triangles for binary STL");
  std::vector<unsigned char> out(84 + 50 * nf, 0);
  std::memcpy(out.data(), header.data(), std::min<std::size_t>(80, header.size()));
  const auto n32 = static_cast<std::uint32_t>(nf);
  std::memcpy(out.data() + 80, &n32, 4);
  // O(#F). Coordinates are written as float32 (the format's limit: ~7 digits).
  for (std::size_t t = 0; t < nf; ++t) {
    const auto ft = static_cast<Eigen::Index>(t);
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = mesh.V.row(static_cast<Eigen::Index>(mesh.F(ft, k))).transpose();
    Eigen::Vector3d nrm = (p[1] - p[0]).cross(p[2] - p[0]);
    const double len = nrm.norm();
    nrm = len > 0 ? Eigen::Vector3d(nrm / len) : Eigen::Vector3d::Zero();
    float rec[12];
    for (int k = 0; k < 3; ++k) rec[k] = static_cast<float>(nrm(k));
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) rec[3 + 3 * v + k] = static_cast<float>(p[v](k));
    std::memcpy(out.data() + 84 + 50 * t, rec, 48);
  }
  write_file_atomic(path, out);
}

}  // namespace millnet::ingest
