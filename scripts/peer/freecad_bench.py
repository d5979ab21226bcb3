# FreeCADCmd script: FreeCAD Path (0.20) on one of millnet's roughing bench pockets.
#
# Run by scripts/peer/freecad_bench.sh; FreeCADCmd takes no script arguments, so the inputs come
# from the environment:
#   PEER_POCKET   the pocket JSON (loops of [x, y, bulge]; first loop the boundary, CCW; islands CW)
#   PEER_OUT      output folder (default /tmp/peer/out)
#   PEER_MARGIN   block margin around the boundary's bounding box, mm (default 10)
#   PEER_STOCK_ZPOS  the Job stock's ExtZpos, mm (default 0: stock top = part top = Z 0;
#                    FreeCAD's own default is 1, which makes every op start at Z +1)
#   PEER_DEFLECTION  STL linear deflection, mm (default 0.001: at 0.01 the chords of the r 75 outline
#                    read as a 0.02 mm gouge of an exact arc in simulate)
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

# ---------------------------------------------------------------------------------------------------
# "check" mode, run by plain python3 (no FreeCAD):  python3 freecad_bench.py check POCKET.json PROG.nc SHIFTX SHIFTY
# Reads a program (absolute G0/G1/G2/G3, I/J incremental centres, as FreeCAD's linuxcnc post writes)
# and prints JSON: retractions (millnet's definition: a G0 up to the safe height after cutting, counted
# when the tool goes back down into the material), plunges, rapids below the stock top (Z < 0), and the
# largest lateral wall penetration of the Ø10 tool into the design walls (boundary and islands, exact
# lines and arcs from the pocket JSON, shifted into the program frame), sampled every 0.02 mm along
# every move below Z 0.
# ---------------------------------------------------------------------------------------------------


def _edges(loop, sx, sy):
    out = []
    n = len(loop)
    for i in range(n):
        x0, y0, b = loop[i][0] + sx, loop[i][1] + sy, loop[i][2]
        x1, y1 = loop[(i + 1) % n][0] + sx, loop[(i + 1) % n][1] + sy
        if abs(b) < 1e-12:
            out.append(("L", x0, y0, x1, y1))
        else:
            th = 4 * math.atan(b)  # signed sweep, + = CCW
            L = math.hypot(x1 - x0, y1 - y0)
            r = L / (2 * math.sin(abs(th) / 2))
            nx, ny = -(y1 - y0) / L, (x1 - x0) / L  # left normal of the chord
            d = r * math.cos(th / 2) * (1 if b > 0 else -1)
            cx, cy = (x0 + x1) / 2 + nx * d, (y0 + y1) / 2 + ny * d
            out.append(("A", cx, cy, r, math.atan2(y0 - cy, x0 - cx), th))
    return out


def _in_sweep(a, a0, th):
    t = (a - a0) % (2 * math.pi) if th > 0 else (a0 - a) % (2 * math.pi)
    return t <= abs(th) + 1e-12


def _dist(e, px, py):
    if e[0] == "L":
        _, x0, y0, x1, y1 = e
        dx, dy = x1 - x0, y1 - y0
        t = max(0.0, min(1.0, ((px - x0) * dx + (py - y0) * dy) / (dx * dx + dy * dy)))
        return math.hypot(px - x0 - t * dx, py - y0 - t * dy)
    _, cx, cy, r, a0, th = e
    if _in_sweep(math.atan2(py - cy, px - cx), a0, th):
        return abs(math.hypot(px - cx, py - cy) - r)
    ends = [(cx + r * math.cos(a0), cy + r * math.sin(a0)), (cx + r * math.cos(a0 + th), cy + r * math.sin(a0 + th))]
    return min(math.hypot(px - x, py - y) for x, y in ends)


def _crossings(e, px, py):
    """Crossings of the ray from (px, py) towards +X with edge e (half-open rule at vertices)."""
    if e[0] == "L":
        _, x0, y0, x1, y1 = e
        if (y0 > py) != (y1 > py):
            x = x0 + (py - y0) * (x1 - x0) / (y1 - y0)
            return 1 if x > px else 0
        return 0
    _, cx, cy, r, a0, th = e
    # split the arc into y-monotone pieces to keep the half-open rule exact
    cuts = [a0]
    for k in range(-8, 9):
        a = math.pi / 2 + k * math.pi
        if _in_sweep(a, a0, th) and abs(a - a0) > 0:
            t = (a - a0) % (2 * math.pi) if th > 0 else (a0 - a) % (2 * math.pi)
            if 1e-12 < t < abs(th) - 1e-12:
                cuts.append(a0 + math.copysign(t, th))
    cuts = sorted(set(cuts), key=lambda a: (a - a0) * (1 if th > 0 else -1)) + [a0 + th]
    n = 0
    for a, b in zip(cuts, cuts[1:]):
        ya, yb = cy + r * math.sin(a), cy + r * math.sin(b)
        if (ya > py) != (yb > py):
            s = math.asin(max(-1.0, min(1.0, (py - cy) / r)))
            for cand in (s, math.pi - s):
                lo, hi = min(a, b), max(a, b)
                for kk in range(-3, 4):
                    c = cand + 2 * math.pi * kk
                    if lo - 1e-12 <= c <= hi + 1e-12:
                        if cx + r * math.cos(c) > px:
                            n += 1
                        break
                else:
                    continue
                break
    return n


def check(pocket, nc, sx, sy, radius=5.0, safe_z=3.0, step=0.02):
    spec = json.load(open(pocket))
    loops = [spec["boundary"]] + list(spec.get("islands", []))
    edges = [e for lp in loops for e in _edges(lp, sx, sy)]

    state = {"inside": None}

    def signed(px, py, fresh=False):
        # The side (in / out of the pocket region) can only change across a wall: the ray test runs near
        # walls and at the first sample of every move.
        d = min(_dist(e, px, py) for e in edges)
        if fresh or state["inside"] is None or d < radius + 1.0:
            state["inside"] = sum(_crossings(e, px, py) for e in edges) % 2 == 1
        return d if state["inside"] else -d

    pos = [0.0, 0.0, 10.0]
    motion = None
    st = {"retractions": 0, "plunges": 0, "rapids_below_top": 0, "rapid_len_below_top_mm": 0.0,
          "max_wall_penetration_mm": 0.0, "penetration_line": None, "penetration_xy": None,
          "moves_over_0p01mm": 0, "moves": 0}
    cut_since = retracted = False
    after_rapid = True
    for ln, raw in enumerate(open(nc), 1):
        line = raw.split("(")[0].split(";")[0].strip().upper()
        if not line:
            continue
        words = {}
        for tok in line.replace("\t", " ").split():
            if tok[0].isalpha() and len(tok) > 1:
                if tok[0] == "G":
                    g = float(tok[1:])
                    if g in (0, 1, 2, 3):
                        motion = int(g)
                    continue
                try:
                    words[tok[0]] = float(tok[1:])
                except ValueError:
                    pass
        if motion is None or not any(k in words for k in "XYZ"):
            continue
        to = [words.get("X", pos[0]), words.get("Y", pos[1]), words.get("Z", pos[2])]
        st["moves"] += 1
        # the move as a sampler of (x, y, z)
        if motion in (2, 3):
            cx, cy = pos[0] + words.get("I", 0.0), pos[1] + words.get("J", 0.0)
            r = math.hypot(pos[0] - cx, pos[1] - cy)
            a0 = math.atan2(pos[1] - cy, pos[0] - cx)
            a1 = math.atan2(to[1] - cy, to[0] - cx)
            sw = (a1 - a0) if motion == 3 else (a0 - a1)
            while sw <= 1e-12:
                sw += 2 * math.pi
            sw = sw if motion == 3 else -sw
            length = abs(sw) * r

            def at(t, cx=cx, cy=cy, r=r, a0=a0, sw=sw, z0=pos[2], z1=to[2]):
                a = a0 + sw * t
                return cx + r * math.cos(a), cy + r * math.sin(a), z0 + (z1 - z0) * t
        else:
            length = math.hypot(to[0] - pos[0], to[1] - pos[1])

            def at(t, p=list(pos), q=to):
                return p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t, p[2] + (q[2] - p[2]) * t
        # retractions / plunges, as millnet's pocket metrics count them
        if motion == 0:
            if to[2] >= safe_z - 1e-6 and pos[2] < safe_z - 1e-6 and cut_since:
                retracted, cut_since = True, False
            if min(pos[2], to[2]) < -1e-6 and length > 1e-9:
                st["rapids_below_top"] += 1
                st["rapid_len_below_top_mm"] += length
            after_rapid = True
        else:
            if to[2] < pos[2] - 1e-6 and after_rapid:
                st["plunges"] += 1
                if retracted:
                    st["retractions"] += 1
                retracted = False
            after_rapid = False
            if min(pos[2], to[2]) < 0:
                cut_since = True
        # wall penetration of every move below the stock top
        if min(pos[2], to[2]) < -1e-6:
            n = max(1, int(math.ceil(length / step)))
            worst = 0.0
            for k in range(n + 1):
                x, y, z = at(k / n)
                if z >= -1e-6:
                    continue
                pen = radius - signed(x, y, fresh=(k == 0))
                if pen > worst:
                    worst = pen
                    if pen > st["max_wall_penetration_mm"]:
                        st["max_wall_penetration_mm"] = pen
                        st["penetration_line"] = ln
                        st["penetration_xy"] = [round(x, 3), round(y, 3)]
            if worst > 0.01:
                st["moves_over_0p01mm"] += 1
        pos = to
    st["rapid_len_below_top_mm"] = round(st["rapid_len_below_top_mm"], 3)
    return st


if len(sys.argv) > 1 and sys.argv[1] == "check":
    print(json.dumps(check(sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5]))))
    sys.exit(0)

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
DEFLECTION = float(os.environ.get("PEER_DEFLECTION", "0.001"))
log["stl_linear_deflection_mm"] = DEFLECTION
mesh = MeshPart.meshFromShape(Shape=solid, LinearDeflection=DEFLECTION, AngularDeflection=0.0872665, Relative=False)
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
