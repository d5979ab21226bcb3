#pragma once
// The training's curves (app/learn.cpp's train_model): the leave-one-out curve over α and the
// filtration / verification of every stored vector (the paper's Figures 5 and 6), as CSV and PNG.
#include "millnet/classifier/network.hpp"
#include "millnet/datasets/table.hpp"

#include <filesystem>

namespace millnet::app {

/// loo_curve.csv (alpha, the chosen mode's rms, both modes' figures) and loo_curve.png.
void write_loo_curve(const classifier::Model& model, const std::filesystem::path& out_dir);

/// verification.csv and .png: filtration (self included) and verification (the chosen mode's
/// left-out output) of the true strategy for every stored vector.
void write_verification(const datasets::Table& table, const classifier::LooReport& loo,
                        const std::filesystem::path& out_dir);

}  // namespace millnet::app
