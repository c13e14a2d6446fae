//! The `lgsvi` binary: output contract, configs, and one-line errors on bad input.

use std::process::Command;

fn lgsvi(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lgsvi"))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn main_job_runs_the_papers_rigid_body() {
    let (code, out, _) = lgsvi(&[]);
    assert_eq!(code, 0);
    assert!(out.contains("‖R(10) − R_exact(10)‖_F"), "{out}");
    // The reported error against the reference is below 1e-12 (the integrator's tests pin it).
    let line = out.lines().find(|l| l.contains("R_exact")).unwrap();
    let value: f64 = line
        .split('=')
        .nth(1)
        .unwrap()
        .trim()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(value < 1e-12, "{line}");
}

#[test]
fn json_has_the_contract_fields() {
    let (code, out, err) = lgsvi(&["simulate", "--t-end", "2", "--every", "2"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "times",
        "R",
        "omega",
        "momentum",
        "energy",
        "casimir",
        "spatial_momentum",
        "stats",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    for key in ["steps", "newton_iterations", "wall_time_s"] {
        assert!(v["stats"].get(key).is_some(), "missing stats.{key}");
    }
    assert_eq!(v["times"].as_array().unwrap().len(), 3); // t = 0, 1, 2
    assert_eq!(v["R"][0].as_array().unwrap().len(), 9);
    assert_eq!(v["stats"]["steps"], 4);
    // Ω from the discrete momentum is J⁻¹μ.
    let (w, mu) = (&v["omega"][2], &v["momentum"][2]);
    let j = [3.3, 2.5, 3.4];
    for k in 0..3 {
        let (w, mu) = (w[k].as_f64().unwrap(), mu[k].as_f64().unwrap());
        assert!((w * j[k] - mu).abs() < 1e-12);
    }
}

#[test]
fn csv_and_heavy_top_and_out_file() {
    let dir = std::env::temp_dir().join(format!("lgsvi-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("top.csv");
    let (code, _, err) = lgsvi(&[
        "simulate",
        "--system",
        "heavy-top",
        "--mass",
        "2",
        "--gravity",
        "1",
        "--com",
        "0,0,0.5",
        "--format",
        "csv",
        "--t-end",
        "1",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&file).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with("t,R11,R12,R13"));
    assert_eq!(lines.count(), 3);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn config_files_and_flags_over_them() {
    let dir = std::env::temp_dir().join(format!("lgsvi-cli-config-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("good.toml");
    std::fs::write(
        &good,
        "system = \"rigid-body\"\ninertia-d = [1.3, 2.1, 1.2]\nh = 0.25\nnodes = 6\nt-end = 1.0\n",
    )
    .unwrap();
    let (code, out, err) = lgsvi(&[
        "simulate",
        "--config",
        good.to_str().unwrap(),
        "--nodes",
        "8",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["description"]["settings"]["nodes"], 8); // the flag wins
    assert_eq!(v["description"]["settings"]["h"], 0.25); // the file fills in
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "system = \"rigid-body\"\nnode = 8\n").unwrap();
    let (code, _, err) = lgsvi(&["simulate", "--config", bad.to_str().unwrap()]);
    assert_ne!(code, 0);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("node"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_is_one_line_naming_the_value() {
    for (args, needle) in [
        (vec!["simulate", "--inertia", "1,1,3"], "triangle"),
        (vec!["simulate", "--inertia-d", "1,-2,1"], "positive"),
        (vec!["simulate", "--nodes", "1"], "nodes"),
        (vec!["simulate", "--h", "-0.5"], "-0.5"),
        (vec!["simulate", "--omega0", "1,2"], "omega0"),
        (vec!["simulate", "--omega0", "nan,0,0"], "nan"),
        (
            vec!["simulate", "--attitude0", "1,0,0,0,1,0,0,0,2"],
            "attitude0",
        ),
        (vec!["simulate", "--chart", "quaternion"], "quaternion"),
        (vec!["simulate", "--every", "0", "--t-end", "1"], "every"),
        (
            vec![
                "simulate",
                "--system",
                "heavy-top",
                "--gravity-direction",
                "0,0,0",
            ],
            "non-zero",
        ),
        (
            vec!["simulate", "--system", "heavy-top", "--mass", "-1"],
            "mass",
        ),
    ] {
        let (code, out, err) = lgsvi(&args);
        assert_ne!(code, 0, "{args:?} succeeded: {out}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn a_too_large_step_names_the_step_and_what_to_change() {
    // h = 8 with |Ω| ≈ 2.9 rad/s asks one step to turn by ~23 rad, past the exp chart's 2π.
    let (code, _, err) = lgsvi(&["simulate", "--h", "8", "--t-end", "16"]);
    assert_ne!(code, 0);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("step 0"), "{err}");
    assert!(
        err.contains("shorter step") || err.contains("smaller step"),
        "{err}"
    );
}

#[test]
fn the_example_configs_run() {
    for name in ["rigid_body.toml", "heavy_top.toml"] {
        let path = format!("{}/../configs/{name}", env!("CARGO_MANIFEST_DIR"));
        let (code, out, err) = lgsvi(&["simulate", "--config", &path, "--t-end", "1"]);
        assert_eq!(code, 0, "{name}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["times"].as_array().unwrap().len(), 3, "{name}");
    }
}
