#!/bin/sh
# Rewrites the sample figures from `lgsvi reproduce` (the CLI test
# `main_job_reproduces_the_nine_figures` checks that they are what it writes).
set -eu
cd "$(dirname "$0")/../.."
out=target/samples
cargo run --release --bin lgsvi -- reproduce --quiet --out "$out"
cp "$out/fig1_rigid_body_n_refinement.svg" "$out/fig2_rigid_body_h_refinement.svg" docs/samples/
# The SE(3) and forced-body conservation figures (`simulate --plot`; 10⁴ steps each,
# about 16 s and 1 s).
cargo run --release --bin lgsvi -- simulate --quiet --system orbiting-body --h 0.5 --nodes 8 \
    --t-end 5000 --every 10 --plot docs/samples/orbiting_body_conservation --out /dev/null
cargo run --release --bin lgsvi -- simulate --quiet --config configs/forced_rigid_body.toml \
    --t-end 2500 --every 40 --plot docs/samples/forced_energy_balance --out /dev/null
rm -f docs/samples/orbiting_body_conservation.png docs/samples/forced_energy_balance.png
# The long run's energy figure (docs/performance.md §4; 10⁶ steps and a 36-member trend
# ensemble, about 5 minutes on 2 cores).
cargo run --release --bin lgsvi -- bench --long-run --long-run-members 36 --quiet --out "$out/long-run"
cp "$out/long-run/long_run_energy.svg" docs/samples/
