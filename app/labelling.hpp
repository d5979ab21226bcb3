#pragma once
// Labels by virtual machining for `millnet dataset` (issue 39): every strategy of a part planned,
// machined on a z-map and scored under the aim, or taken from the recipe's labels.json when the
// part's file and the settings match; the agreement of the simulated best with a recipe's labels.
#include "settings.hpp"

#include "millnet/datasets/build.hpp"
#include "millnet/datasets/io/labels.hpp"

#include <string>
#include <utility>
#include <vector>

namespace millnet::app {

/// One part's strategies as the simulation ranked them (or as labels.json kept them).
struct SimulatedLabel {
  datasets_io::PartLabel label;
  int recipe_label = 0;  ///< the recipe's label (0 for a part labelled by simulation)
};

/// The labels of recipe parts `which`: from the recipe's labels.json where the part's file bytes and
/// the settings match, by simulation otherwise (one process or MPI ranks, a unit = a part). In
/// `which` order, on rank 0; empty on the other ranks. A part that fails stops the build, naming it.
[[nodiscard]] std::vector<SimulatedLabel> labels_of(const datasets::Recipe& recipe,
                                                    const std::vector<std::size_t>& which,
                                                    const FinishSettings& settings);

/// Whether labels computed under the settings `cached` hold under `current` (both as
/// recipe_from_config writes them): equal once every key either lacks is filled in at its schema
/// default, so that a key added to /finish, /simulate, /cutting or /machine at a default that keeps
/// the old behaviour leaves the cache valid. /finish/rest (the job's rest operation, which no label
/// plans) is not compared. A `cached` text the schema refuses never matches.
[[nodiscard]] bool same_label_settings(const std::string& cached, const std::string& current);

/// A label's figures as the manifest echoes them (under "labelling").
[[nodiscard]] Json figures_json(const datasets_io::PartLabel& label);

/// The agreement of the simulated best with the recipe's labels, per label: JSON and a Markdown table.
[[nodiscard]] std::pair<Json, std::string> agreement(const std::vector<SimulatedLabel>& labels,
                                                     const datasets::Recipe& recipe);

/// The name of a 1-based strategy slot, "?" outside the names.
[[nodiscard]] std::string strategy_name(const std::vector<std::string>& names, int slot);

}  // namespace millnet::app
