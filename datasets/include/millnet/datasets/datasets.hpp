#pragma once
// Facade of millnet::datasets. The CLI's path:
//   auto parts = datasets::generate_default_parts("datasets/parts", {.seed = 7, .per_family = 6});
//   datasets::Recipe r; r.parts = datasets::to_part_specs(parts); r.generate = {7, 6, 110};
//   datasets::write_table(datasets::build_table(r, progress.callback()), out_dir);
//   auto table = datasets::read_table(out_dir / "vectors.csv");
#include "millnet/datasets/build.hpp"
#include "millnet/datasets/generator.hpp"
#include "millnet/datasets/hash.hpp"
#include "millnet/datasets/rng.hpp"
#include "millnet/datasets/table.hpp"
#include "millnet/datasets/tolerances.hpp"
