// The part's frame and the holder check (frame.hpp).
#include "millnet/job/frame.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace millnet::job {

namespace {
std::string fixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}
}  // namespace

std::string Frame::header() const { return "frame: Z 0 = stock top = part top + " + fixed(top_allowance, 3) + " mm"; }

Frame frame_of(const ingest::Mesh& mesh, double top_allowance_mm) {
  if (mesh.V.rows() == 0) throw Error("frame: the part's mesh has no vertices");
  if (!(std::isfinite(top_allowance_mm) && top_allowance_mm >= 0))
    throw Error("frame: the stock above the part must be a finite number >= 0 mm, got " +
                format_double(top_allowance_mm));
  Frame f;
  f.part_top = mesh.V.col(2).maxCoeff();
  f.part_bottom = mesh.V.col(2).minCoeff();
  f.top_allowance = top_allowance_mm;
  f.stock_top = f.part_top + top_allowance_mm;
  f.width = mesh.V.col(0).maxCoeff();
  f.depth = mesh.V.col(1).maxCoeff();
  return f;
}

void check_reach(const tooling::Cutter& cutter, std::string_view label, double depth_mm, std::string_view what) {
  const double stick = cutter.reach_mm;
  if (!(stick > 0) || !(depth_mm > stick)) return;
  throw Error(std::string(label) + ": " + std::string(what) + " reaches " + fixed(depth_mm, 2) +
              " mm below the stock top, beyond the tool's stick-out " + format_double(stick) + " mm by " +
              fixed(depth_mm - stick, 2) + " mm: the holder would hit the stock");
}

}  // namespace millnet::job
