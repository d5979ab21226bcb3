#pragma once
// The model file: JSON, versioned, readable without millnet.
//
//   {"format": "millnet-model", "version": 1,
//    "alpha": α, "strategies": [K names],
//    "normalizer": {"mean": [D], "std": [D]},
//    "stored": {"inputs": [[D]…N], "outputs": [[K]…N], "groups": [N source names]},
//    "unfamiliar": {"threshold": d², "factor": k, "percentile": p},
//    "features": {"raster_mm", "grid", "inputs", "aspect_feature"}   (Model::input_spec; optional),
//    "loo": {"mode": "part"|"vector", "d2_scale", "curve": [{"alpha","rms_part","rms_vector",
//            "accuracy_part","accuracy_vector"}…], "part": {…optimum}, "vector": {…optimum},
//            "rms_part_at_alpha", "rms_vector_at_alpha", "accuracy_part_at_alpha",
//            "accuracy_vector_at_alpha", "full_passes", "neighbour_cache_used"}}
//
// Keys are written in sorted order. Inputs are raw (the normalizer is re-applied on load). Numbers are written as the shortest text
// that reads back to the same double, so save → load is bit-exact. The filtration/verification
// matrices are not stored (the CLI writes them to verification.csv).
#include <filesystem>

#include "millnet/classifier/network.hpp"

namespace millnet::classifier_io {

inline constexpr int kModelFormatVersion = 1;

/// Writes the model atomically (temporary file + rename). Throws millnet::Error on I/O failure or
/// on a non-finite number (JSON has none).
void save_model(const classifier::Model& model, const std::filesystem::path& path);

/// Reads a model file. Throws millnet::Error naming the file and the key path (e.g.
/// "model.json: stored.inputs[3][17]: expected a number, got string") on a missing key, wrong
/// type, shape mismatch, wrong "format" or unsupported "version", and on a "features" object whose
/// "inputs" is not grid² (+ 1 with the aspect feature) or not the stored inputs' width.
[[nodiscard]] classifier::Model load_model(const std::filesystem::path& path);

}  // namespace millnet::classifier_io
