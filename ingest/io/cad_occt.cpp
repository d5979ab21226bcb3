// The only file that sees Open CASCADE (ARCHITECTURE.md: heavy dependencies stay private at the edge),
// compiled with it only when CMake found it (MILLNET_CAD); otherwise CAD files are a clear error.
#include "cad.hpp"
#include "weld_key.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <unordered_map>

#if MILLNET_HAVE_CAD
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESEntity.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <mutex>
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

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
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

Mesh tessellate(const TopoDS_Shape& shape, const CadOptions& o, std::size_t* faces) {
  // Sequential (isInParallel = false): the triangles do not depend on the thread count.
  BRepMesh_IncrementalMesh mesher(shape, o.chord_tolerance_mm, Standard_False, o.angular_deflection_rad,
                                  Standard_False);
  using Key = detail::WeldKey<std::uint64_t>;
  detail::WeldIndex<std::uint64_t> index;
  std::vector<double> V;
  std::vector<std::int32_t> F;
  std::vector<std::int32_t> local;
  *faces = 0;
  // O(#nodes + #triangles) over all faces (expected, hash map).
  for (TopExp_Explorer x(shape, TopAbs_FACE); x.More(); x.Next()) {
    const TopoDS_Face& face = TopoDS::Face(x.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    ++*faces;
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

// Open CASCADE's static parameters (Interface_Static) are process-wide: one read at a time.
std::mutex g_occt;

Mesh load_locked(const fs::path& path, const CadOptions& options, MeshReport* report) {
  const std::string name = path.string();
  const std::string ext = lower(path.extension().string());
  const bool step = ext == ".step" || ext == ".stp";
  const std::string bytes = read_file(path);
  if (step)
    check_step_frame(bytes, name);
  else
    check_iges_frame(bytes, name);
  silence_occt();
  CadReport cad;
  cad.format = step ? "STEP" : "IGES";
  cad.chord_tolerance_mm = options.chord_tolerance_mm;
  cad.angular_deflection_rad = options.angular_deflection_rad;
  cad.body = options.body;
  TopoDS_Shape root;
  Handle(XSControl_WorkSession) ws;
  if (step) {
    STEPControl_Reader reader;
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    if (reader.ReadFile(name.c_str()) != IFSelect_RetDone)
      throw file_error(name, "cannot read STEP file (Open CASCADE's parser refused it)");
    TColStd_SequenceOfAsciiString len, ang, solid;
    reader.FileUnits(len, ang, solid);
    if (len.Length() >= 1) {
      const Unit u = step_unit(len.Value(1).ToCString());
      cad.file_unit = u.name;
      cad.file_unit_mm = u.mm;
    }
    reader.TransferRoots();
    if (reader.NbShapes() > 0) root = reader.OneShape();
    ws = reader.WS();
  } else {
    IGESControl_Reader reader;
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    if (reader.ReadFile(name.c_str()) != IFSelect_RetDone)
      throw file_error(name, "cannot read IGES file (Open CASCADE's parser refused it)");
    const Handle(IGESData_IGESModel) model = reader.IGESModel();
    if (!model.IsNull()) {
      const Unit u = iges_unit(model->GlobalSection().UnitFlag());
      cad.file_unit = u.name;
      cad.file_unit_mm = u.mm;
    }
    reader.TransferRoots();
    if (reader.NbShapes() > 0) root = reader.OneShape();
    ws = reader.WS();
  }
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
  Mesh m = tessellate(chosen, options, &cad.faces);
  if (m.F.rows() == 0)
    throw file_error(
        name, "no triangles: Open CASCADE's mesher produced none for the " + std::to_string(cad.faces) + " faces");
  if (report) {
    report->notes.push_back(cad.format + ": " + std::to_string(cad.faces) + " faces of " +
                            std::to_string(bodies.size()) + " bodies tessellated (chord " +
                            std::to_string(options.chord_tolerance_mm) + " mm, angle " +
                            std::to_string(options.angular_deflection_rad) + " rad)");
    report->is_cad = true;
    report->cad = cad;
  }
  return m;
}

}  // namespace

Mesh load_cad(const fs::path& path, const CadOptions& options, MeshReport* report) {
  const std::string name = path.string();
  std::lock_guard<std::mutex> lock(g_occt);
  try {
    return load_locked(path, options, report);
  } catch (const Error&) {
    throw;
  } catch (const Standard_Failure& e) {
    throw file_error(name, std::string("Open CASCADE failed: ") +
                               one_line(e.GetMessageString() ? e.GetMessageString() : "") + " (" +
                               e.DynamicType()->Name() + ")");
  }
}

#endif

}  // namespace millnet::ingest::detail
