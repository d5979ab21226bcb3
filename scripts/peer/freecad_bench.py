# FreeCADCmd script: FreeCAD Path (0.20) on one of millnet's roughing bench pockets.
#
# Run by scripts/peer/freecad_bench.sh; FreeCADCmd takes no script arguments, so the inputs come
# from the environment:
#   PEER_POCKET   the pocket JSON (loops of [x, y, bulge]; first loop the boundary, CCW; islands CW)
#   PEER_OUT      output folder (default /tmp/peer/out)
#   PEER_MARGIN   block margin around the boundary's bounding box, mm (default 10)
#   PEER_STOCK_ZPOS  the Job stock's ExtZpos, mm (default 0: stock top = part top = Z 0;
#                    FreeCAD's own default is 1, which makes every op start at Z +1)
#
# Writes PEER_OUT/<pocket>.stl, <pocket>.freecad_offset.nc, <pocket>.freecad_adaptive.nc,
# <pocket>.freecad.json (what was set, FreeCAD's resolved op properties) and <pocket>.FCStd.
#
# Frame. millnet simulate recentres a mesh (its bounding box's minimum corner goes to X 0 Y 0)
# and puts program Z 0 at the mesh top + /rough/top_allowance_mm. So the part is built with its
# block's minimum corner at X 0 Y 0: the pocket is translated by (margin - xmin, margin - ymin)
# (written to the JSON as "shift"), the block top is Z 0 and its bottom Z -10, the floor Z -5.
# The G-code is therefore in that translated frame (times are translation invariant).
import json
import math
import os
import sys
import time
import importlib

import FreeCAD
import Part
import Path
import Mesh
import MeshPart
from FreeCAD import Vector

import PathScripts.PathJob as PathJob
import PathScripts.PathPocketShape as PathPocketShape
import PathScripts.PathAdaptive as PathAdaptive
import PathScripts.PathLog as PathLog

POCKET = os.environ["PEER_POCKET"]
OUT = os.environ.get("PEER_OUT", "/tmp/peer/out")
MARGIN = float(os.environ.get("PEER_MARGIN", "10"))
STOCK_ZPOS = float(os.environ.get("PEER_STOCK_ZPOS", "0"))
DEPTH = 5.0
BLOCK = 10.0
TOOL_D = 10.0
STEPOVER_PCT = 50
HFEED, VFEED = 1500.0, 300.0  # mm/min
SPINDLE = 3000

stem = os.path.splitext(os.path.basename(POCKET))[0]
os.makedirs(OUT, exist_ok=True)
log = {"pocket": POCKET, "stem": stem, "freecad_version": ".".join(FreeCAD.Version()[0:3]),
       "freecad_version_full": FreeCAD.Version()}

with open(POCKET) as fp:
    spec = json.load(fp)
loops = [spec["boundary"]] + list(spec.get("islands", []))
xs = [v[0] for v in spec["boundary"]]
ys = [v[1] for v in spec["boundary"]]


def bulge_bbox(loop):
    """Bounding box of a loop including its arcs (sampled)."""
    pts = []
    n = len(loop)
    for i in range(n):
        x0, y0, b = loop[i]
        x1, y1 = loop[(i + 1) % n][0], loop[(i + 1) % n][1]
        if abs(b) < 1e-12:
            pts.append((x0, y0))
            continue
        th = 4 * math.atan(b)
        L = math.hypot(x1 - x0, y1 - y0)
        r = L / (2 * math.sin(abs(th) / 2))
        mx, my = (x0 + x1) / 2, (y0 + y1) / 2
        nx, ny = -(y1 - y0) / L, (x1 - x0) / L  # left normal of the chord
        d = r * math.cos(th / 2)  # signed: centre lies left of the chord for CCW arcs < 180
        cx, cy = mx + nx * d * (1 if b > 0 else -1), my + ny * d * (1 if b > 0 else -1)
        a0 = math.atan2(y0 - cy, x0 - cx)
        for k in range(0, 257):
            a = a0 + th * k / 256
            pts.append((cx + r * math.cos(a), cy + r * math.sin(a)))
    return (min(p[0] for p in pts), min(p[1] for p in pts), max(p[0] for p in pts), max(p[1] for p in pts))


bx0, by0, bx1, by1 = bulge_bbox(spec["boundary"])
SHIFT = (MARGIN - bx0, MARGIN - by0)
W, H = (bx1 - bx0) + 2 * MARGIN, (by1 - by0) + 2 * MARGIN
log.update({"shift": SHIFT, "block_mm": [W, H, BLOCK], "boundary_bbox": [bx0, by0, bx1, by1], "margin": MARGIN})


def P(x, y, z):
    return Vector(x + SHIFT[0], y + SHIFT[1], z)


def loop_wire(loop, z):
    edges = []
    n = len(loop)
    for i in range(n):
        x0, y0, b = loop[i]
        x1, y1 = loop[(i + 1) % n][0], loop[(i + 1) % n][1]
        p0, p1 = P(x0, y0, z), P(x1, y1, z)
        if abs(b) < 1e-12:
            edges.append(Part.LineSegment(p0, p1).toShape())
        else:
            # arc midpoint: chord midpoint minus sagitta (b * L / 2) along the chord's left normal
            L = math.hypot(x1 - x0, y1 - y0)
            nx, ny = -(y1 - y0) / L, (x1 - x0) / L
            s = b * L / 2
            mx, my = (x0 + x1) / 2 - nx * s, (y0 + y1) / 2 - ny * s
            edges.append(Part.Arc(p0, P(mx, my, z), p1).toShape())
    w = Part.Wire(Part.__sortEdges__(edges))
    assert w.isClosed(), "loop is not closed"
    return w


t0 = time.time()
zfloor = -DEPTH
region = Part.Face(loop_wire(loops[0], zfloor))
for isl in loops[1:]:
    region = region.cut(Part.Face(loop_wire(isl, zfloor)))
cavity = region.extrude(Vector(0, 0, DEPTH + 1.0))  # from the floor up through the top
block = Part.makeBox(W, H, BLOCK, Vector(0, 0, -BLOCK))
solid = block.cut(cavity).removeSplitter()
assert solid.isValid() and len(solid.Solids) == 1, "part solid is not one valid solid"
log["pocket_area_mm2"] = region.Area
log["part_volume_mm3"] = solid.Volume

doc = FreeCAD.newDocument("peer_" + stem)
part = doc.addObject("Part::Feature", "Part")
part.Shape = solid
doc.recompute()

# The part as STL (fine tessellation)
mesh = MeshPart.meshFromShape(Shape=solid, LinearDeflection=0.01, AngularDeflection=0.0872665, Relative=False)
stl = os.path.join(OUT, stem + ".stl")
mesh.write(stl)
log["stl"] = stl
log["stl_triangles"] = mesh.CountFacets

# --- Path Job -------------------------------------------------------------------------------------
job = PathJob.Create("Job", [part])
job.PostProcessor = "linuxcnc"
job.PostProcessorArgs = "--no-show-editor"
stock = job.Stock
log["stock_default_ext_mm"] = {k: getattr(stock, k).Value for k in
                               ("ExtXneg", "ExtXpos", "ExtYneg", "ExtYpos", "ExtZneg", "ExtZpos")}
stock.ExtZpos = STOCK_ZPOS
stock.ExtZneg = 0
doc.recompute()
log["stock_bbox"] = [stock.Shape.BoundBox.XMin, stock.Shape.BoundBox.YMin, stock.Shape.BoundBox.ZMin,
                     stock.Shape.BoundBox.XMax, stock.Shape.BoundBox.YMax, stock.Shape.BoundBox.ZMax]

tc = job.Tools.Group[0]
tc.Label = "TC: 10mm Endmill"
tool = tc.Tool
log["tool_shape"] = getattr(tool, "BitShape", None)
tool.Diameter = TOOL_D
if hasattr(tool, "ShankDiameter"):
    tool.ShankDiameter = TOOL_D
if hasattr(tool, "CuttingEdgeHeight"):
    tool.CuttingEdgeHeight = 30
if hasattr(tool, "Length"):
    tool.Length = 50
tc.HorizFeed = "%g mm/min" % HFEED  # FreeCAD velocities are mm/s unless a unit is given
tc.VertFeed = "%g mm/min" % VFEED
tc.SpindleSpeed = SPINDLE
doc.recompute()
log["tool_diameter"] = tool.Diameter.Value

model = job.Model.Group[0]  # the job's clone of the part
floor = None
for i, f in enumerate(model.Shape.Faces):
    bb = f.BoundBox
    if abs(bb.ZMax - zfloor) < 1e-6 and abs(bb.ZMin - zfloor) < 1e-6:
        assert floor is None, "more than one floor face"
        floor = "Face%d" % (i + 1)
assert floor, "no floor face at Z %g" % zfloor
log["floor_face"] = floor

PROPS = ["StartDepth", "FinalDepth", "StepDown", "FinishDepth", "SafeHeight", "ClearanceHeight",
         "CutMode", "OffsetPattern", "StartAt", "StepOver", "ExtraOffset", "MinTravel", "KeepToolDown",
         "UseOutline", "ZigZagAngle", "UseStartPoint", "HandleMultipleFeatures", "EnableRotation",
         "OperationType", "Side", "Tolerance", "LiftDistance", "KeepToolDownRatio", "StockToLeave",
         "ForceInsideOut", "FinishingProfile", "UseHelixArcs", "HelixAngle", "HelixConeAngle",
         "HelixDiameterLimit", "CoolantMode"]


def props(op):
    d = {}
    for p in PROPS:
        if hasattr(op, p):
            v = getattr(op, p)
            d[p] = v.UserString if hasattr(v, "UserString") else v
    return d


def check_depths(op, name):
    # The stock top is Z 0 (ExtZpos 0): the op starts there and ends on the floor in one step.
    log[name + "_defaults"] = props(op)


# 1. Pocket (PocketShape on the floor face), Offset pattern, 50 %, climb, defaults otherwise
pocket = PathPocketShape.Create("Pocket", parentJob=job)
pocket.Base = [(model, [floor])]
doc.recompute()
check_depths(pocket, "offset")
pocket.OffsetPattern = "Offset"
pocket.StepOver = STEPOVER_PCT
pocket.CutMode = "Climb"
doc.recompute()

# 2. Adaptive clearing, 50 %, defaults otherwise (helix ramp angle at its default)
adaptive = PathAdaptive.Create("Adaptive", parentJob=job)
adaptive.Base = [(model, [floor])]
doc.recompute()
check_depths(adaptive, "adaptive")
adaptive.OperationType = "Clearing"
adaptive.Side = "Inside"
adaptive.StepOver = STEPOVER_PCT
doc.recompute()

log["offset"] = props(pocket)
log["adaptive"] = props(adaptive)
for op, name in ((pocket, "offset"), (adaptive, "adaptive")):
    n = len(op.Path.Commands)
    log[name + "_commands"] = n
    if n < 5:
        raise SystemExit("FreeCAD %s op produced no path (%d commands): %s" % (name, n, op.Path.toGCode()))


# --- Post, each op separately, like PathPost's "Fixture" ordering: fixture (G54 + G0 to clearance),
# tool controller (M6 T1, G43 H1, M3 S), operation -------------------------------------------------
class _Fixture:
    def __init__(self, name, z):
        self.Label = self.Name = name
        self.Path = Path.Path([Path.Command(name), Path.Command("G0 Z%s" % z)])


from PathScripts.post import linuxcnc_post  # noqa: E402

clear_z = job.Stock.Shape.BoundBox.ZMax + job.SetupSheet.ClearanceHeightOffset.Value
for op, name in ((pocket, "offset"), (adaptive, "adaptive")):
    post = importlib.reload(linuxcnc_post)  # fresh module globals per file
    nc = os.path.join(OUT, "%s.freecad_%s.nc" % (stem, name))
    post.export([_Fixture("G54", clear_z), tc, op], nc, "--no-show-editor")
    log[name + "_nc"] = nc
    log[name + "_freecad_cycle_time"] = getattr(op, "CycleTime", None)

doc.saveAs(os.path.join(OUT, stem + ".FCStd"))
log["freecad_seconds"] = time.time() - t0
with open(os.path.join(OUT, stem + ".freecad.json"), "w") as fp:
    json.dump(log, fp, indent=1, default=str)
print("PEER_DONE", stem, json.dumps({k: log[k] for k in ("offset_commands", "adaptive_commands", "shift")}))
