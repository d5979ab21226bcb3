#!/usr/bin/env bash
# Issue 39 §3: the feature ablation on a library labelled by simulation (datasets/README.md).
#   bench/feature_ablation.sh [CONFIG]   (default: the tool-shop library preset, the default config's library)
# Builds the model-vector table (labels from the config's cache, the rest simulated: minutes per
# part) and prints leave-one-part-out top-1 and regret for the heights alone and with each feature.
set -euo pipefail
cd "$(dirname "$0")/.."
config=${1:-configs/presets/shop-library.json}
out=$(mktemp -d)
build/app/millnet dataset --config "$config" --out "$out/table"
parts=$(python3 -c "import json,sys,os; c=json.load(open(sys.argv[1])); print(os.path.normpath(os.path.join(os.path.dirname(sys.argv[1]), c['dataset'].get('parts_dir','../datasets/parts'))))" "$config")
build/bench/feature_ablation "$out/table" "$parts" 9 25
