// The only file that sees Open CASCADE (ARCHITECTURE.md: heavy dependencies stay private at the edge),
// compiled with it only when CMake found it (MILLNET_CAD); otherwise CAD files are a clear error.
//
// A STEP or IGES file is hostile input to Open CASCADE 7.6, which crashes, recurses without bound,
// hangs or reads in part on damaged files (issue 42). So, in order:
//  1. frame check (start and end markers) and the structural pre-scan (cad_scan.hpp: nesting,
//     reference cycles, self-containing assemblies, numbers and units out of range) in this process;
//  2. the read, the transfer check, the size check, the tessellation's estimate and the
//     tessellation itself in a child process (cad_isolate.hpp) with Open CASCADE's signal handling
//     on, under time and memory limits: a crash there is one line naming the file, never the end of
//     the caller (a batch goes on with its next part);
//  3. the mesh comes back over a pipe (the vertices and triangles as raw doubles and int32).
#if MILLNET_HAVE_CAD
// OCC_CATCH_SIGNALS (in the reader's child process) turns a signal into a C++ exception. Debian's
// Open CASCADE 7.6 is built with the same definition (libTKernel exports
// Standard_ErrorHandler::Callback::RegisterCallback), so the headers agree with the library.
#define OCC_CONVERT_SIGNALS 1
#endif
#include "cad.hpp"
#include "cad_estimate.hpp"
#include "cad_isolate.hpp"
#include "cad_scan.hpp"
#include "weld_key.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/budget.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <unordered_map>

#if MILLNET_HAVE_CAD
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepLProp_CLProps.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESEntity.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <OSD.hxx>
#include <OSD_Exception.hxx>
#include <OSD_Signal.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <Standard_OutOfMemory.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <numbers>
#include <unordered_set>
#endif

namespace millnet::ingest::detail {

namespace fs = std::filesystem;

const std::vector<std::string>& cad_extensions() {
  static const std::vector<std::string> ext = {".step", ".stp", ".iges", ".igs"};
  return ext;
}

#if !MILLNET_HAVE_CAD

bool cad_supported() { return false; }

Mesh load_cad(const fs::path& path, const CadOptions&, MeshReport*) {
  throw file_error(path.string(),
                   "built without CAD support (STEP/IGES need Open CASCADE: install libocct-data-exchange-dev "
                   "libocct-modeling-algorithms-dev and rebuild with -DMILLNET_CAD=ON)");
}

#else

bool cad_supported() { return true; }

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Library text for a one-line message: line breaks become spaces, other control bytes \xNN, at most
// 160 characters (bytes of UTF-8 names pass).
std::string one_line(const std::string& in) {
  std::string s;
  for (const char c : in) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n' || c == '\r' || c == '\t')
      s += ' ';
    else if (u < 0x20 || u == 0x7F)
      s += quote_bytes(std::string_view(&c, 1));
    else
      s += c;
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  s.erase(0, std::min(s.size(), s.find_first_not_of(' ')));
  if (s.size() > 160) s = s.substr(0, 157) + "...";
  return s;
}

struct Unit {
  std::string name;  // "" = not stated
  double mm = 1.0;
};

// STEP SI_UNIT names (prefix + METRE) and CONVERSION_BASED_UNIT names as Open CASCADE reports them.
Unit step_unit(const std::string& raw) {
  const std::string u = lower(raw);
  if (u.empty()) return {};
  if (u == "millimetre" || u == "millimeter" || u == "mm") return {"mm", 1.0};
  if (u == "centimetre" || u == "centimeter" || u == "cm") return {"cm", 10.0};
  if (u == "metre" || u == "meter" || u == "m") return {"m", 1000.0};
  if (u == "micrometre" || u == "micrometer" || u == "um") return {"um", 0.001};
  if (u == "inch" || u == "in") return {"inch", 25.4};
  if (u == "foot" || u == "ft") return {"foot", 304.8};
  return {u, 1.0};  // stated but unknown to us: Open CASCADE has converted anyway
}

// IGES global section, parameter 14 (unit flag).
Unit iges_unit(int flag) {
  switch (flag) {
    case 1: return {"inch", 25.4};
    case 2: return {"mm", 1.0};
    case 4: return {"foot", 304.8};
    case 5: return {"mile", 1609344.0};
    case 6: return {"m", 1000.0};
    case 7: return {"km", 1.0e6};
    case 8: return {"mil", 0.0254};
    case 9: return {"um", 0.001};
    case 10: return {"cm", 10.0};
    case 11: return {"microinch", 0.0000254};
    default: return {};
  }
}

// Cheap structural checks first, so that a truncated or foreign file gets a message a person can act
// on instead of Open CASCADE's partial read (a STEP file cut short still parses up to the cut).
void check_step_frame(const std::string& bytes, const std::string& name) {
  const std::size_t head = std::min<std::size_t>(bytes.size(), 4096);
  if (bytes.substr(0, head).find("ISO-10303-21") == std::string::npos)
    throw file_error(name, "not a STEP file (expected it to start with \"ISO-10303-21;\")");
  const std::size_t tail = bytes.size() > 4096 ? bytes.size() - 4096 : 0;
  if (bytes.find("END-ISO-10303-21", tail) == std::string::npos)
    throw file_error(name, "truncated STEP file (no \"END-ISO-10303-21;\" at its end)");
}

void check_iges_frame(const std::string& bytes, const std::string& name) {
  // Fixed 80-column lines; column 73 holds the section letter: S G D P, then one T line at the end.
  std::size_t first_end = bytes.find('\n');
  const std::string first = bytes.substr(0, first_end == std::string::npos ? bytes.size() : first_end);
  if (first.size() < 73 || (first[72] != 'S' && first[72] != 'F' && first[72] != 'C'))
    throw file_error(name, "not an IGES file (expected 80-column lines starting with the S section)");
  std::size_t e = bytes.size();
  while (e > 0 && std::isspace(static_cast<unsigned char>(bytes[e - 1]))) --e;
  const std::size_t b = bytes.rfind('\n', e == 0 ? 0 : e - 1);
  const std::string last = bytes.substr(b == std::string::npos ? 0 : b + 1, e - (b == std::string::npos ? 0 : b + 1));
  if (last.size() < 73 || last[72] != 'T')
    throw file_error(name, "truncated IGES file (its last line is not the T (terminate) section)");
}

// Open CASCADE prints through its default messenger (stdout): silenced once per process.
void silence_occt() {
  static std::once_flag once;
  std::call_once(once, [] { Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream)); });
}

struct Body {
  TopoDS_Shape shape;
  std::string name;
};

std::string entity_name(const Handle(XSControl_WorkSession) & ws, const TopoDS_Shape& shape) {
  if (ws.IsNull()) return {};
  const Handle(XSControl_TransferReader) tr = ws->TransferReader();
  if (tr.IsNull()) return {};
  const Handle(Standard_Transient) ent = tr->EntityFromShapeResult(shape, 1);
  if (ent.IsNull()) return {};
  if (const auto item = Handle(StepRepr_RepresentationItem)::DownCast(ent); !item.IsNull() && !item->Name().IsNull())
    return item->Name()->ToCString();
  if (const auto ig = Handle(IGESData_IGESEntity)::DownCast(ent); !ig.IsNull() && ig->HasName())
    return ig->NameValue()->ToCString();
  return {};
}

// Solids, then shells outside solids, then faces outside shells, in the file's order.
std::vector<Body> bodies_of(const TopoDS_Shape& root, const Handle(XSControl_WorkSession) & ws) {
  std::vector<Body> out;
  for (TopExp_Explorer x(root, TopAbs_SOLID); x.More(); x.Next()) out.push_back({x.Current(), {}});
  for (TopExp_Explorer x(root, TopAbs_SHELL, TopAbs_SOLID); x.More(); x.Next()) out.push_back({x.Current(), {}});
  for (TopExp_Explorer x(root, TopAbs_FACE, TopAbs_SHELL); x.More(); x.Next()) out.push_back({x.Current(), {}});
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::string n = one_line(entity_name(ws, out[i].shape));
    out[i].name = n.empty() ? "body " + std::to_string(i + 1) : n;
  }
  return out;
}

std::size_t pick_body(const std::vector<Body>& bodies, const std::string& wanted, const std::string& name) {
  const bool digits =
      !wanted.empty() && std::all_of(wanted.begin(), wanted.end(), [](char c) { return c >= '0' && c <= '9'; });
  std::string list;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    list += (i ? ", " : "") + std::to_string(i + 1) + " \"" + bodies[i].name + "\"";
  if (digits && wanted.size() < 9) {
    const std::size_t k = std::stoul(wanted);
    if (k >= 1 && k <= bodies.size()) return k - 1;
    throw file_error(name, "no body " + wanted + " (--body / /mesh/cad_body; the file has " +
                               std::to_string(bodies.size()) + ": " + list + ")");
  }
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == wanted) return i;
  throw file_error(name, "no body named \"" + wanted + "\" (--body / /mesh/cad_body; available: " + list + ")");
}

Mesh tessellate(const TopoDS_Shape& shape, const CadOptions& o, const Handle(XSControl_WorkSession) & ws,
                CadReport& cad) {
  // Sequential (isInParallel = false): the triangles do not depend on the thread count.
  BRepMesh_IncrementalMesh mesher(shape, o.chord_tolerance_mm, Standard_False, o.angular_deflection_rad,
                                  Standard_False);
  using Key = detail::WeldKey<std::uint64_t>;
  detail::WeldIndex<std::uint64_t> index;
  std::vector<double> V;
  std::vector<std::int32_t> F;
  std::vector<std::int32_t> local;
  std::size_t* faces = &cad.faces;
  *faces = 0;
  cad.triangle_face.clear();
  cad.face_names.clear();
  // O(#nodes + #triangles) over all faces (expected, hash map).
  for (TopExp_Explorer x(shape, TopAbs_FACE); x.More(); x.Next()) {
    const TopoDS_Face& face = TopoDS::Face(x.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    ++*faces;
    cad.face_names.push_back(one_line(entity_name(ws, face)));
    if (tri.IsNull()) continue;
    const gp_Trsf T = loc.Transformation();
    local.assign(static_cast<std::size_t>(tri->NbNodes()) + 1, -1);
    for (Standard_Integer i = 1; i <= tri->NbNodes(); ++i) {
      gp_Pnt p = tri->Node(i);
      p.Transform(T);
      const double xyz[3] = {p.X() + 0.0, p.Y() + 0.0, p.Z() + 0.0};  // + 0.0: −0 and +0 join
      Key key{};
      std::memcpy(&key.a, &xyz[0], 8);
      std::memcpy(&key.b, &xyz[1], 8);
      std::memcpy(&key.c, &xyz[2], 8);
      const auto [it, inserted] = index.try_emplace(key, static_cast<std::int32_t>(V.size() / 3));
      if (inserted) V.insert(V.end(), xyz, xyz + 3);
      local[static_cast<std::size_t>(i)] = it->second;
    }
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (Standard_Integer t = 1; t <= tri->NbTriangles(); ++t) {
      Standard_Integer n1 = 0, n2 = 0, n3 = 0;
      tri->Triangle(t).Get(n1, n2, n3);
      if (reversed) std::swap(n2, n3);
      const std::int32_t a = local[static_cast<std::size_t>(n1)], b = local[static_cast<std::size_t>(n2)],
                         c = local[static_cast<std::size_t>(n3)];
      if (a == b || b == c || a == c) continue;  // collapsed by the join
      F.insert(F.end(), {a, b, c});
      cad.triangle_face.push_back(static_cast<std::int32_t>(*faces));
    }
  }
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(V.size() / 3), 3);
  for (std::size_t i = 0; i < V.size(); ++i)
    m.V(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = V[i];
  m.F.resize(static_cast<Eigen::Index>(F.size() / 3), 3);
  for (std::size_t i = 0; i < F.size(); ++i)
    m.F(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) = F[i];
  return m;
}

/// What a read gives back, in this process or from the child.
struct CadResult {
  Mesh mesh;
  CadReport cad;
  std::vector<std::string> notes;
};

// ---- The transfer check: what a damaged file lost (issue 42 §2) ----

struct Fails {
  std::size_t count = 0;
  std::string first;
};

Fails count_fails(Interface_CheckIterator checks) {
  Fails f;
  for (checks.Start(); checks.More(); checks.Next()) {  // O(checks)
    const Handle(Interface_Check)& c = checks.Value();
    if (c.IsNull() || !c->HasFailed()) continue;
    if (f.count++ == 0 && c->NbFails() > 0) f.first = one_line(c->CFail(1));
  }
  return f;
}

std::string plural(std::size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// One line of what was lost ("" = nothing): faces and roots read against the file's, failed
/// transfers, and the pre-scan's damage (references to missing entities, syntax errors).
std::string losses(const CadScan& scan, std::size_t faces_read, int roots, int roots_read, const Fails& transfer) {
  std::vector<std::string> parts;
  if (scan.faces > faces_read)
    parts.push_back(std::to_string(faces_read) + " of its " + plural(scan.faces, "face", "faces") + " (" +
                    std::to_string(scan.faces - faces_read) + " lost)");
  if (roots_read < roots)
    parts.push_back(std::to_string(roots_read) + " of its " + plural(static_cast<std::size_t>(roots), "root", "roots") +
                    " transferred");
  if (transfer.count > 0)
    parts.push_back(plural(transfer.count, "failed transfer", "failed transfers") +
                    (transfer.first.empty() ? "" : " (first: " + transfer.first + ")"));
  if (scan.unresolved_references > 0)
    parts.push_back(plural(scan.unresolved_references, "reference", "references") + " to missing entities (" +
                    scan.first_unresolved_reference + ")");
  if (scan.syntax_errors > 0)
    parts.push_back(plural(scan.syntax_errors, "syntax error", "syntax errors") + " (" + scan.first_syntax_error + ")");
  std::string s;
  for (std::size_t k = 0; k < parts.size(); ++k) s += (k ? "; " : "") + parts[k];
  return s;
}

std::size_t distinct_faces(const TopoDS_Shape& root) {
  std::unordered_set<const void*> seen;
  for (TopExp_Explorer x(root, TopAbs_FACE); x.More(); x.Next()) seen.insert(x.Current().TShape().get());
  return seen.size();
}

/// No coordinate of a part may lie beyond this, mm (the G-code reader's travel bound too): a part
/// larger than any machine's travel is a unit or a number gone wrong, refused before meshing.
constexpr double kMaxPartExtentMm = 1e5;

void check_size(const TopoDS_Shape& shape, const std::string& name, const CadReport& cad) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, Standard_False);
  if (box.IsVoid()) return;  // no geometry: the mesher makes nothing, said below
  double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
  box.Get(x0, y0, z0, x1, y1, z1);
  const double extent = std::max({x1 - x0, y1 - y0, z1 - z0});
  const double far = std::max({std::abs(x0), std::abs(y0), std::abs(z0), std::abs(x1), std::abs(y1), std::abs(z1)});
  if (box.IsOpen() || !(far < 1e99))  // Open CASCADE's "infinite" is 2e100
    throw file_error(name,
                     "the part is unbounded or reaches beyond 1e99 mm (a face without a boundary, a number gone "
                     "wrong: a damaged file?): refused before meshing");
  if (!(extent <= kMaxPartExtentMm) || !(far <= kMaxPartExtentMm))
    throw file_error(name, "the part reaches " + format_count(std::max(extent, far)) + " mm (in the file's unit " +
                               (cad.file_unit.empty() ? "mm" : cad.file_unit) + "), beyond " +
                               format_size(kMaxPartExtentMm) +
                               " mm, more than any machine travels: refused before meshing (is the unit right?)");
}

// Open CASCADE's static parameters (Interface_Static) are process-wide: one read at a time.
std::mutex g_occt;

/// Read, check, tessellate: everything that touches Open CASCADE. Throws millnet::Error (or an
/// Open CASCADE exception, which the callers turn into one).
CadResult read_here(const fs::path& path, bool step, const CadScan& scan, const CadOptions& options) {
  const std::string name = path.string();
  silence_occt();
  CadResult out;
  CadReport& cad = out.cad;
  cad.format = step ? "STEP" : "IGES";
  cad.chord_tolerance_mm = options.chord_tolerance_mm;
  cad.angular_deflection_rad = options.angular_deflection_rad;
  cad.body = options.body;
  TopoDS_Shape root;
  Handle(XSControl_WorkSession) ws;
  int roots = 0, roots_read = 0;
  std::unique_ptr<XSControl_Reader> reader;
  if (step) {
    auto r = std::make_unique<STEPControl_Reader>();
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    if (r->ReadFile(name.c_str()) != IFSelect_RetDone)
      throw file_error(name, "cannot read STEP file (Open CASCADE's parser refused it)");
    TColStd_SequenceOfAsciiString len, ang, solid;
    r->FileUnits(len, ang, solid);
    if (len.Length() >= 1) {
      const Unit u = step_unit(len.Value(1).ToCString());
      cad.file_unit = u.name;
      cad.file_unit_mm = u.mm;
    }
    reader = std::move(r);
  } else {
    auto r = std::make_unique<IGESControl_Reader>();
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    if (r->ReadFile(name.c_str()) != IFSelect_RetDone)
      throw file_error(name, "cannot read IGES file (Open CASCADE's parser refused it)");
    const Handle(IGESData_IGESModel) model = r->IGESModel();
    if (!model.IsNull()) {
      const Unit u = iges_unit(model->GlobalSection().UnitFlag());
      cad.file_unit = u.name;
      cad.file_unit_mm = u.mm;
    }
    reader = std::move(r);
  }
  ws = reader->WS();
  const Fails model = count_fails(ws->ModelCheckList());
  roots = reader->NbRootsForTransfer();
  roots_read = reader->TransferRoots();
  if (reader->NbShapes() > 0) root = reader->OneShape();
  Fails transfer;
  if (!ws->TransferReader().IsNull() && !ws->TransferReader()->TransientProcess().IsNull())
    transfer = count_fails(ws->TransferReader()->TransientProcess()->CheckList(Standard_False));
  const std::size_t faces_read = root.IsNull() ? 0 : distinct_faces(root);
  const std::string lost = losses(scan, faces_read, roots, roots_read, transfer);
  if (!lost.empty()) {
    if (!options.allow_partial)
      throw file_error(name, "damaged " + cad.format + " file, read only in part: " + lost +
                                 "; refused (set /mesh/allow_partial_cad to true to use what was read)");
    cad.partial = "read in part (allowed by /mesh/allow_partial_cad): " + lost;
    out.notes.push_back(cad.partial);
  }
  if (model.count > 0)
    out.notes.push_back(plural(model.count, "entity", "entities") + " with errors in the file (first: " + model.first +
                        ")");
  if (root.IsNull()) throw file_error(name, "no solid, shell or face in this " + cad.format + " file");
  const std::vector<Body> bodies = bodies_of(root, ws);
  if (bodies.empty()) throw file_error(name, "no solid, shell or face in this " + cad.format + " file");
  for (const auto& b : bodies) cad.bodies.push_back(b.name);
  TopoDS_Shape chosen;
  if (options.body.empty()) {
    TopoDS_Compound all;
    BRep_Builder builder;
    builder.MakeCompound(all);
    for (const auto& b : bodies) builder.Add(all, b.shape);
    chosen = all;
  } else {
    chosen = bodies[pick_body(bodies, options.body, name)].shape;
  }
  check_size(chosen, name, cad);
  const TessellationEstimate est =
      estimate_tessellation(chosen, options.chord_tolerance_mm, options.angular_deflection_rad);
  cad.estimated_triangles = est.triangles;
  try {
    check_work(
        {"tessellating " + plural(est.faces, "face", "faces") + " at chord " + format_size(options.chord_tolerance_mm) +
             " mm and " + format_size(options.angular_deflection_rad) + " rad (≈ " + format_count(est.triangles) +
             " triangles)",
         est.steps, "mesher steps", est.triangles * kMesherBytesPerTriangle + est.placed * kMeshBytesPerTriangle},
        options.limits);
  } catch (const Error& e) {
    throw file_error(name, e.what());
  }
  out.mesh = tessellate(chosen, options, ws, cad);
  if (out.mesh.F.rows() == 0)
    throw file_error(
        name, "no triangles: Open CASCADE's mesher produced none for the " + std::to_string(cad.faces) + " faces");
  out.notes.push_back(cad.format + ": " + std::to_string(cad.faces) + " faces of " + std::to_string(bodies.size()) +
                      " bodies tessellated (chord " + std::to_string(options.chord_tolerance_mm) + " mm, angle " +
                      std::to_string(options.angular_deflection_rad) + " rad)");
  return out;
}

// ---- The answer over the pipe ----

void put(std::string& o, const void* p, std::size_t n) { o.append(static_cast<const char*>(p), n); }
void put_u64(std::string& o, std::uint64_t v) { put(o, &v, 8); }
void put_f64(std::string& o, double v) { put(o, &v, 8); }
void put_str(std::string& o, const std::string& s) {
  put_u64(o, s.size());
  o += s;
}

std::string encode(const CadResult& r) {
  std::string o = "M";
  const CadReport& c = r.cad;
  put_str(o, c.format);
  put_str(o, c.file_unit);
  put_f64(o, c.file_unit_mm);
  put_f64(o, c.chord_tolerance_mm);
  put_f64(o, c.angular_deflection_rad);
  put_u64(o, c.bodies.size());
  for (const auto& b : c.bodies) put_str(o, b);
  put_str(o, c.body);
  put_u64(o, c.faces);
  put_str(o, c.partial);
  put_f64(o, c.estimated_triangles);
  put_u64(o, r.notes.size());
  for (const auto& n : r.notes) put_str(o, n);
  put_u64(o, static_cast<std::uint64_t>(r.mesh.V.rows()));
  put(o, r.mesh.V.data(), static_cast<std::size_t>(r.mesh.V.size()) * sizeof(double));
  put_u64(o, static_cast<std::uint64_t>(r.mesh.F.rows()));
  put(o, r.mesh.F.data(), static_cast<std::size_t>(r.mesh.F.size()) * sizeof(std::int32_t));
  put(o, c.triangle_face.data(), c.triangle_face.size() * sizeof(std::int32_t));  // one per triangle
  put_u64(o, c.face_names.size());
  for (const auto& n : c.face_names) put_str(o, n);
  return o;
}

class Decoder {
public:
  Decoder(const std::string& s, const std::string& name) : s_(s), name_(name) {}
  void get(void* p, std::size_t n) {
    if (n > s_.size() - at_) throw file_error(name_, "the reader's process answered with a truncated mesh");
    std::memcpy(p, s_.data() + at_, n);
    at_ += n;
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    get(&v, 8);
    return v;
  }
  double f64() {
    double v = 0;
    get(&v, 8);
    return v;
  }
  std::string str() {
    const std::uint64_t n = u64();
    if (n > s_.size() - at_) throw file_error(name_, "the reader's process answered with a truncated mesh");
    std::string v = s_.substr(at_, n);
    at_ += n;
    return v;
  }
  std::size_t left() const { return s_.size() - at_; }

private:
  const std::string& s_;
  const std::string& name_;
  std::size_t at_ = 1;  // after the tag
};

CadResult decode(const std::string& answer, const std::string& name) {
  Decoder d(answer, name);
  CadResult r;
  CadReport& c = r.cad;
  c.format = d.str();
  c.file_unit = d.str();
  c.file_unit_mm = d.f64();
  c.chord_tolerance_mm = d.f64();
  c.angular_deflection_rad = d.f64();
  for (std::uint64_t k = d.u64(); k > 0; --k) c.bodies.push_back(d.str());
  c.body = d.str();
  c.faces = d.u64();
  c.partial = d.str();
  c.estimated_triangles = d.f64();
  for (std::uint64_t k = d.u64(); k > 0; --k) r.notes.push_back(d.str());
  const std::uint64_t nv = d.u64();
  if (nv > d.left() / 24) throw file_error(name, "the reader's process answered with a truncated mesh");
  r.mesh.V.resize(static_cast<Eigen::Index>(nv), 3);
  d.get(r.mesh.V.data(), nv * 24);
  const std::uint64_t nf = d.u64();
  if (nf > d.left() / 16) throw file_error(name, "the reader's process answered with a truncated mesh");
  r.mesh.F.resize(static_cast<Eigen::Index>(nf), 3);
  d.get(r.mesh.F.data(), nf * 12);
  c.triangle_face.resize(nf);
  d.get(c.triangle_face.data(), nf * 4);
  const std::uint64_t names = d.u64();
  if (names != c.faces) throw file_error(name, "the reader's process answered with a truncated mesh");
  for (std::uint64_t k = 0; k < names; ++k) c.face_names.push_back(d.str());
  if (d.left() != 0) throw file_error(name, "the reader's process answered with a truncated mesh");
  return r;
}

std::string mib(double bytes) { return format_size(std::round(bytes / (1024.0 * 1024.0))); }

/// An Open CASCADE exception as one line: a signal it caught (a crash), memory, or its message.
std::string occt_failure(const std::string& name, const std::string& format, const Standard_Failure& e,
                         const CadOptions& options) {
  const std::string what = one_line(e.GetMessageString() ? e.GetMessageString() : "");
  if (e.IsKind(STANDARD_TYPE(OSD_Signal)) || e.IsKind(STANDARD_TYPE(OSD_Exception)))
    return name + ": the " + format + " reader crashed (" + e.DynamicType()->Name() + ": " + what +
           ", caught by Open CASCADE's signal handling): the file is damaged; nothing was read from it";
  if (e.IsKind(STANDARD_TYPE(Standard_OutOfMemory)))
    return name + ": the " + format + " reader ran out of memory (limit " + mib(options.limits.max_memory_bytes) +
           " MiB: --max-memory-mb, /limits/max_memory_mb)";
  return name + ": Open CASCADE failed: " + what + " (" + e.DynamicType()->Name() + ")";
}

/// The read in a child process (cad_isolate.hpp); every way it can end becomes a result or one
/// millnet::Error naming the file.
CadResult read_isolated(const fs::path& path, bool step, const CadScan& scan, const CadOptions& options) {
  const std::string name = path.string(), format = step ? "STEP" : "IGES";
  ChildLimits limits;
  limits.wall_seconds = options.timeout_s;
  limits.memory_bytes = options.limits.max_memory_bytes;
  const ChildOutcome o = run_in_child(
      [&](const std::function<void(const std::string&)>& send) {
        OSD::SetSignal(OSD_SignalMode_Set, Standard_False);  // signals → exceptions; floating point untouched
        std::string answer;
        try {
          OCC_CATCH_SIGNALS
          answer = encode(read_here(path, step, scan, options));
        } catch (const Error& e) {
          answer = std::string("E") + e.what();
        } catch (const Standard_Failure& e) {
          answer = "E" + occt_failure(name, format, e, options);
        } catch (const std::bad_alloc&) {
          answer = "E" + name + ": the " + format + " reader ran out of memory (limit " +
                   mib(options.limits.max_memory_bytes) + " MiB: --max-memory-mb, /limits/max_memory_mb)";
        } catch (const std::exception& e) {
          answer = "E" + name + ": the " + format + " reader failed: " + one_line(e.what());
        }
        send(answer);
      },
      limits);
  using End = ChildOutcome::End;
  switch (o.end) {
    case End::Answered:
      if (o.answer[0] == 'E') throw Error(o.answer.substr(1));
      return decode(o.answer, name);
    case End::Signal:
      throw file_error(name, "the " + format + " reader crashed (signal " + std::to_string(o.signal) + ", " +
                                 signal_name(o.signal) + "): the file is damaged; nothing was read from it");
    case End::TimedOut:
      throw file_error(name, "the " + format + " reader took more than " + format_size(options.timeout_s) +
                                 " s and was stopped: a damaged file, or a part too large to read");
    case End::OutOfMemory:
      throw file_error(name, "the " + format + " reader needed more than " + mib(options.limits.max_memory_bytes) +
                                 " MiB and was stopped (--max-memory-mb, /limits/max_memory_mb)");
    case End::NoFork:
      throw file_error(name, "cannot start the " + format + " reader's process (" + std::strerror(o.status) + ")");
    case End::Exited: break;
  }
  throw file_error(name,
                   "the " + format + " reader ended without an answer (exit status " + std::to_string(o.status) + ")");
}

}  // namespace

Mesh load_cad(const fs::path& path, const CadOptions& options, MeshReport* report) {
  const std::string name = path.string();
  if (!(options.chord_tolerance_mm > 0) || !std::isfinite(options.chord_tolerance_mm))
    throw file_error(name, "the chord tolerance must be a finite number > 0 mm (/mesh/chord_tolerance_mm)");
  if (!(options.angular_deflection_rad > 0) || !std::isfinite(options.angular_deflection_rad))
    throw file_error(name, "the angular deflection must be a finite number > 0 rad (/mesh/angular_deflection_rad)");
  const std::string ext = lower(path.extension().string());
  const bool step = ext == ".step" || ext == ".stp";
  const std::string bytes = read_file(path);
  if (step)
    check_step_frame(bytes, name);
  else
    check_iges_frame(bytes, name);
  const CadScan scan = step ? scan_step(bytes) : scan_iges(bytes);
  if (!scan.refusal.empty()) throw file_error(name, scan.refusal + "; refused before reading");
  CadResult r;
  {
    std::lock_guard<std::mutex> lock(g_occt);
    if (options.isolate) {
      r = read_isolated(path, step, scan, options);
    } else {
      try {
        r = read_here(path, step, scan, options);
      } catch (const Standard_Failure& e) {
        throw Error(occt_failure(name, step ? "STEP" : "IGES", e, options));
      }
    }
  }
  if (report) {
    for (auto& n : r.notes) report->notes.push_back(std::move(n));
    report->is_cad = true;
    report->cad = std::move(r.cad);
  }
  return std::move(r.mesh);
}

#endif

}  // namespace millnet::ingest::detail
