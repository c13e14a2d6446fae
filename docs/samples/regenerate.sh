#!/bin/sh
# Rewrites the sample figures from `lgsvi reproduce` (the CLI test
# `main_job_reproduces_the_nine_figures` checks that they are what it writes).
set -eu
cd "$(dirname "$0")/../.."
out=target/samples
cargo run --release --bin lgsvi -- reproduce --quiet --out "$out"
cp "$out/fig1_rigid_body_n_refinement.svg" "$out/fig2_rigid_body_h_refinement.svg" docs/samples/
