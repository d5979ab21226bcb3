#pragma once
// The tool-shop library (issue 39 §2): parts like the ones tool shops finish, in eight families —
// mould cavities and cores with draft walls and fillets, ribbed plates, plates with bores and
// counterbores, B-spline (bicubic) free-form surfaces, pockets with free-form floors, blends of
// steep and shallow areas, terraced cores — footprint sides 40–200 mm (log-uniform, aspect ≤ 1.8),
// deterministic from a seed. Unlike the five textbook families (generator.hpp) these parts carry no
// strategy label: they are labelled by virtual machining (datasets/README.md).
//
// Every part is a closed height-field solid in generator.hpp's mesh layout (top grid row-major,
// then the bottom ring and centre), sampled every `spacing_mm` (about; the grid spans each side
// exactly). Its relief (top's highest − lowest point) stays ≤ kShopMaxReliefMm, within the reach of
// the default Ø2 ball (45 mm) with its holder clear.
#include "millnet/datasets/generator.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace millnet::datasets {

enum class ShopFamily : int {
  Cavity = 0,             ///< a block with a drafted, filleted cavity (flat or free-form floor, sometimes a core in it)
  Core = 1,               ///< a plate with a drafted, filleted boss (flat, domed or pocketed top)
  RibbedPlate = 2,        ///< a plate with thin drafted ribs (rounded or flat tops), sometimes a frame
  BoredPlate = 3,         ///< a plate with blind bores and counterbores, pockets and round bosses
  FreeformSurface = 4,    ///< a bicubic B-spline surface over the whole footprint
  FreeformPocket = 5,     ///< a block with steep-walled pockets whose floors are B-spline surfaces
  SteepShallowBlend = 6,  ///< a gentle B-spline field with a raised area behind a steep, filleted scarp
  TerracedCore = 7,       ///< 2–4 nested drafted levels with fillets
};
inline constexpr int kShopFamilies = 8;
inline constexpr double kShopSideMinMm = 40.0, kShopSideMaxMm = 200.0;
inline constexpr double kShopMaxReliefMm = 40.0;

/// "cavity", "core", "ribbed_plate", "bored_plate", "freeform_surface", "freeform_pocket",
/// "steep_shallow_blend", "terraced_core".
[[nodiscard]] std::string shop_family_name(ShopFamily f);

/// Part k of the library is family k mod kShopFamilies, index k / kShopFamilies within it: a
/// library of n parts is the first n of every larger one.
[[nodiscard]] ShopFamily shop_family_of(int k);

/// Part k of the library, deterministic in (k, seed) (its own random stream: asking for more
/// parts never changes the earlier ones). O(a·b / spacing²).
[[nodiscard]] GeneratedMesh make_shop_part(int k, std::uint64_t seed, double spacing_mm = 0.8);

/// Writes parts 0 … count−1 as binary STL (<dir>/shop_NNNN_<family>.stl, atomically) and
/// <dir>/parts.csv ("name,file,label", label 0: none) and returns the list. Same arguments ⇒
/// identical bytes. O(count · a·b / spacing²).
std::vector<GeneratedPart> generate_shop_parts(const std::filesystem::path& dir, std::uint64_t seed, int count,
                                               double spacing_mm = 0.8);

namespace detail {
/// Cross-section of a drafted wall with fillets, as a height over the horizontal distance d from
/// the wall's foot line (d > 0 towards the raised side): 0 for d ≤ −t₁, the foot fillet (radius
/// r_foot, concave), the straight wall at draft_deg from the vertical, the top fillet (radius r_top,
/// convex), then h. Tangent-continuous; radii are shrunk together when the wall is too short for
/// both. draft_deg in [0.5, 89].
[[nodiscard]] double filleted_step(double d, double h, double draft_deg, double r_foot, double r_top);
}  // namespace detail

}  // namespace millnet::datasets
