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
# The long run's energy figure (docs/notes/performance.md §4; 10⁶ steps and a 36-member trend
# ensemble, about 5 minutes on 2 cores).
cargo run --release --bin lgsvi -- bench --long-run --long-run-members 36 --quiet --out "$out/long-run"
cp "$out/long-run/long_run_energy.svg" docs/samples/
# Tolerance-driven runs (docs/notes/tolerance.md): the heavy top's estimate against the true
# local error, its --tol runs at T = 10, and the long run with nodes chosen per step.
cargo run --release --bin lgsvi -- converge --quiet --study estimate --system heavy-top \
    --plot docs/samples/estimate_vs_truth_heavy_top
cargo run --release --bin lgsvi -- converge --quiet --study tolerance --system heavy-top \
    --plot docs/samples/tolerance_heavy_top
rm -f docs/samples/estimate_vs_truth_heavy_top.png docs/samples/tolerance_heavy_top.png
cargo run --release --bin lgsvi -- bench --quiet --out "$out/bench"
cp "$out/bench/bench_B_T100.svg" docs/samples/
cargo run --release --bin lgsvi -- bench --long-run --long-run-tol 1e-13 --long-run-members 36 \
    --quiet --out "$out/long-run-tol"
cp "$out/long-run-tol/long_run_energy.svg" docs/samples/long_run_energy_adaptive.svg
# Betts's minimum-time reorientation (docs/guide/optimal.md; 100 steps, about 0.2 s).
cargo run --release --bin lgsvi -- optimize --quiet --inertia 5621,4547,2364 \
    --attitude-final 2.6179938779914944,0,0 --torque-max 50 --cost time --steps 100 \
    --nodes 8 --plot "$out/betts" --out /dev/null
cp "$out/betts_torques.svg" docs/samples/betts_minimum_time_torques.svg
# A least-time manoeuvre in space (docs/guide/optimal.md; 20 steps, about 2 s).
cargo run --release --bin lgsvi -- optimize --quiet --space --inertia 3,4,5.5 --mass 10 \
    --attitude-final 1.5,0.4,-0.9 --position-final 2,1,0 --torque-max 0.1 --force-max 0.2 \
    --cost time --steps 20 --nodes 8 --plot "$out/space" --out /dev/null
cp "$out/space_torques.svg" docs/samples/space_minimum_time_torques.svg
cp "$out/space_forces.svg" docs/samples/space_minimum_time_forces.svg
