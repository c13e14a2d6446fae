//! `lgsvi montecarlo`: members that depend on (seed, member) alone, whatever the thread
//! count; a row that `lgsvi simulate` given the row's parameters reproduces bit for bit,
//! and `--replay`; failures listed with seed and cause, never dropped; bad input refused
//! naming the flag or key.

mod common;

use common::temp_dir;

/// `lgsvi args`, on `threads` threads where given.
fn lgsvi(args: &[&str], threads: Option<&str>) -> (i32, String, String) {
    let dir = std::env::current_dir().expect("a working directory");
    match threads {
        Some(threads) => common::run_in(&dir, args, &[("RAYON_NUM_THREADS", threads)]),
        None => common::run_in(&dir, args, &[]),
    }
}

const RUN: [&str; 12] = [
    "montecarlo",
    "--members",
    "40",
    "--seed",
    "9",
    "--disperse-omega",
    "0.02",
    "--disperse-inertia",
    "0.01",
    "--disperse-attitude",
    "2",
    "--quiet",
];

/// `(header, rows)` of a members.csv.
fn table(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

#[test]
fn members_are_the_same_on_one_thread_or_two_and_simulate_reproduces_a_row() {
    let dir = temp_dir("determinism");
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let out = dir.join(format!("threads-{threads}"));
        let mut args = RUN.to_vec();
        args.extend([
            "--t-end",
            "5",
            "--tol",
            "1e-10",
            "--out",
            out.to_str().unwrap(),
        ]);
        let (code, _, err) = lgsvi(&args, Some(threads));
        assert_eq!(code, 0, "{err}");
        outputs.push(std::fs::read(out.join("members.csv")).unwrap());
    }
    assert_eq!(
        outputs[0], outputs[1],
        "members.csv differs between 1 and 2 threads"
    );
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("threads-2").join("summary.json")).unwrap(),
    )
    .unwrap();
    // Every member takes the nominal's step (one time grid for the envelopes).
    let h = summary["settings"]["h"].as_f64().unwrap().to_string();
    let (header, rows) = table(&dir.join("threads-2").join("members.csv"));
    assert_eq!(rows.len(), 40);
    assert_eq!(&header[..3], ["member", "status", "J_11"]);
    assert_eq!(header.len(), 2 + 9 + 9 + 3 + 1 + 9 + 3);
    let row = &rows[13];
    assert_eq!((row[0].as_str(), row[1].as_str()), ("13", "ok"));
    // simulate with the row's drawn J, R₀, Ω₀ (and the nominal's flags) ends on the row's
    // final state, bit for bit (every float printed to round-trip).
    let j = row[2..11].join(",");
    let r0 = row[11..20].join(",");
    let w0 = row[20..23].join(",");
    let (code, out, err) = lgsvi(
        &[
            "simulate",
            "--inertia-tensor",
            &j,
            "--attitude0",
            &r0,
            "--omega0",
            &w0,
            "--t-end",
            "5",
            "--tol",
            "1e-10",
            "--h",
            &h,
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    let last = |key: &str| -> Vec<f64> {
        json[key]
            .as_array()
            .unwrap()
            .last()
            .unwrap()
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let parse =
        |cells: &[String]| -> Vec<f64> { cells.iter().map(|c| c.parse().unwrap()).collect() };
    assert_eq!(last("R"), parse(&row[24..33]));
    assert_eq!(last("omega"), parse(&row[33..36]));
    // --replay 13 writes that member's whole trajectory, the same last state.
    let mut args = RUN.to_vec();
    args.extend(["--t-end", "5", "--tol", "1e-10", "--replay", "13"]);
    let (code, out, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let replay: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(replay["R"], json["R"]);
    assert_eq!(replay["omega"], json["omega"]);
    // The summary: every member finished, the rates' statistics over them, and the
    // envelopes: at t = 0 the attitude departure's percentiles are those of the drawn
    // starts (2° per axis), ordered, and the same on one thread or two.
    let envelope = &summary["envelopes"]["channels"]["attitude_departure_deg"];
    let at = |p: &str, k: usize| envelope[p][k].as_f64().unwrap();
    let t = summary["envelopes"]["t"].as_array().unwrap();
    assert!(t.len() >= 2 && t[0] == 0.0);
    for k in 0..t.len() {
        assert!(at("p1", k) <= at("p50", k) && at("p50", k) <= at("p99", k));
    }
    assert!((1.0..8.0).contains(&at("p50", 0)), "{}", at("p50", 0));
    let other: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("threads-1").join("summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(other["envelopes"], summary["envelopes"]);
    for figure in ["envelope_attitude.png", "envelope_energy.svg"] {
        assert!(dir.join("threads-2").join(figure).exists(), "{figure}");
    }
    assert_eq!(summary["finished"], 40);
    assert_eq!(summary["failed"], 0);
    assert_eq!(
        summary["final_omega"]["covariance"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    assert_eq!(
        summary["dispersions"]["inertia"]["distribution"],
        "truncated_normal"
    );
}

/// Members whose steps fail (spins the Cayley chart cannot follow at h = 1) are listed
/// with their seed and cause, their rows marked, the rest written; exit status 3.
#[test]
fn failed_members_are_listed_not_dropped() {
    let dir = temp_dir("failures");
    let out = dir.join("run");
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--members",
            "20",
            "--disperse-omega",
            "2",
            "--h",
            "1",
            "--chart",
            "cayley",
            "--t-end",
            "4",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("members failed") && err.contains("summary.json"),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let failed = summary["failed"].as_u64().unwrap();
    assert!(failed > 0 && failed < 20, "{failed}");
    let (_, rows) = table(&out.join("members.csv"));
    assert_eq!(rows.len(), 20);
    let marked = rows.iter().filter(|r| r[1] == "failed").count() as u64;
    assert_eq!(marked, failed);
    for failure in summary["failures"].as_array().unwrap() {
        assert_eq!(failure["seed"], 0);
        assert!(
            failure["error"]
                .as_str()
                .unwrap()
                .contains("cayley chart's reach"),
            "{failure}"
        );
        let member = failure["member"].as_u64().unwrap() as usize;
        assert_eq!(rows[member][1], "failed");
    }
}

#[test]
fn bad_input_is_refused_naming_the_flag_or_key() {
    let dir = temp_dir("bad");
    let taken = dir.join("taken");
    std::fs::create_dir_all(&taken).unwrap();
    std::fs::write(taken.join("members.csv"), "member\n").unwrap();
    let config = dir.join("bad.toml");
    std::fs::write(
        &config,
        "[montecarlo.dispersions]\nomegas = { distribution = \"normal\", sigma = 0.1 }\n",
    )
    .unwrap();
    let out = dir.join("out");
    for (args, needles) in [
        (vec!["--members", "0"], vec!["--members 0", "from 1"]),
        (
            vec!["--disperse-omega", "-1"],
            vec!["--disperse-omega -1", "≥ 0"],
        ),
        (
            vec!["--disperse-inertia", "0.2"],
            vec![
                "--disperse-inertia 0.2",
                "triangle inequality",
                "below 0.260870",
            ],
        ),
        (
            vec!["--system", "se3-body"],
            vec!["--system se3-body", "rigid-body, heavy-top"],
        ),
        (vec!["--plot", "p"], vec!["--plot"]),
        (
            vec!["--config", config.to_str().unwrap()],
            vec!["[montecarlo.dispersions]", "omegas"],
        ),
    ] {
        let mut full = vec!["montecarlo", "--quiet", "--out", out.to_str().unwrap()];
        full.extend(args.iter().copied());
        let (code, _, err) = lgsvi(&full, None);
        assert_ne!(code, 0, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        for needle in needles {
            assert!(err.contains(needle), "{args:?}: {err}");
        }
    }
    // An output folder that holds another run.
    let (code, _, err) = lgsvi(
        &["montecarlo", "--quiet", "--out", taken.to_str().unwrap()],
        None,
    );
    assert_ne!(code, 0);
    assert!(err.contains("holds another run"), "{err}");
}

#[test]
fn stop_times_per_member_match_simulate_and_are_summarised() {
    let dir = temp_dir("stop");
    let out = dir.join("run");
    // An axisymmetric nominal (J = diag(1, 1, 1.8)), rates dispersed: Ω₁ falls through 0
    // near π/(2 · 0.8 · 1.5) ≈ 1.31 for each member.
    let args = [
        "montecarlo",
        "--inertia",
        "1,1,1.8",
        "--omega0",
        "0.3,0,1.5",
        "--h",
        "0.25",
        "--nodes",
        "12",
        "--t-end",
        "10",
        "--members",
        "30",
        "--seed",
        "4",
        "--disperse-omega",
        "0.05",
        "--stop-when",
        "omega_1<0",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = lgsvi(&args, None);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = table(&out.join("members.csv"));
    assert_eq!(header.last().map(String::as_str), Some("t_stop"));
    let row = &rows[7];
    let t_stop: f64 = row.last().unwrap().parse().unwrap();
    let (code, json, err) = lgsvi(
        &[
            "simulate",
            "--inertia-tensor",
            &row[2..11].join(","),
            "--attitude0",
            &row[11..20].join(","),
            "--omega0",
            &row[20..23].join(","),
            "--h",
            "0.25",
            "--nodes",
            "12",
            "--t-end",
            "10",
            "--stop-when",
            "omega_1<0",
            "--quiet",
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(json["description"]["stopped"]["t"].as_f64(), Some(t_stop));
    // The member's row ends at the end of the step holding its stop.
    let t_end: f64 = row[23].parse().unwrap();
    assert!(t_end >= t_stop && t_end - t_stop < 0.25);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let stop = &summary["stop"];
    assert_eq!(stop["members_stopped"], 30);
    let mut times: Vec<f64> = rows
        .iter()
        .map(|r| r.last().unwrap().parse().unwrap())
        .collect();
    times.sort_by(f64::total_cmp);
    // The exact sample median: the ⌈0.5 · 30⌉ = 15th smallest.
    assert_eq!(stop["time_percentiles"]["p50"].as_f64(), Some(times[14]));
    let counts: u64 = stop["histogram"]["counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .sum();
    assert_eq!(counts, 30);
    for ext in ["png", "svg"] {
        assert!(out.join(format!("stop_times.{ext}")).exists());
    }
}

#[test]
fn an_interrupted_run_resumes_to_the_uninterrupted_result() {
    let dir = temp_dir("resume");
    let (whole, cut) = (dir.join("whole"), dir.join("cut"));
    let mut args = RUN.to_vec();
    args.extend(["--t-end", "5"]);
    let with_out = |out: &std::path::Path, extra: &[&str]| {
        let mut a = args.clone();
        a.extend(["--out", out.to_str().unwrap()]);
        a.extend(extra);
        lgsvi(&a.iter().map(|s| &**s).collect::<Vec<_>>(), None)
    };
    let (code, _, err) = with_out(&whole, &[]);
    assert_eq!(code, 0, "{err}");
    // Interrupted after 17 of 40 members, a row half written after them.
    let (code, _, err) = with_out(&cut, &["--interrupt-after", "17"]);
    assert_ne!(code, 0);
    assert!(err.contains("17 of 40"), "{err}");
    assert!(cut.join("checkpoint.json").exists());
    let (_, rows) = table(&cut.join("members.csv"));
    assert_eq!(rows.len(), 17);
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .open(cut.join("members.csv"))
        .unwrap();
    std::io::Write::write_all(&mut file, b"17,ok,3.3,0.0").unwrap();
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--resume",
            "--quiet",
            "--out",
            cut.to_str().unwrap(),
        ],
        None,
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(whole.join("members.csv")).unwrap(),
        std::fs::read(cut.join("members.csv")).unwrap(),
        "the resumed members.csv differs from the uninterrupted one"
    );
    let summary = |d: &std::path::Path| -> serde_json::Value {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap())
                .unwrap();
        v.as_object_mut().unwrap().remove("wall_time_s");
        v
    };
    assert_eq!(summary(&whole), summary(&cut));
    assert!(!cut.join("checkpoint.json").exists());
    // A complete run has nothing to resume; other flags beside --resume are refused.
    let (code, _, err) = lgsvi(
        &["montecarlo", "--resume", "--out", cut.to_str().unwrap()],
        None,
    );
    assert_ne!(code, 0);
    assert!(
        err.contains("--resume") && err.contains("no interrupted run"),
        "{err}"
    );
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--resume",
            "--members",
            "3",
            "--out",
            cut.to_str().unwrap(),
        ],
        None,
    );
    assert_ne!(code, 0);
    assert!(err.contains("only --out"), "{err}");
}

/// A dispersion the config's table sets and the body cannot take names the file and key.
#[test]
fn a_config_dispersion_the_body_cannot_take_names_the_file() {
    let dir = temp_dir("config-mass");
    let config = dir.join("mc.toml");
    std::fs::write(
        &config,
        "[montecarlo]\nmembers = 3\n[montecarlo.dispersions]\nmass = { distribution = \"uniform\", half_width = 0.1 }\n",
    )
    .unwrap();
    let out = dir.join("run");
    let (code, _, err) = lgsvi(
        &[
            "montecarlo",
            "--config",
            config.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        None,
    );
    assert_ne!(code, 0);
    assert!(
        err.contains("mc.toml") && err.contains("[montecarlo.dispersions]") && err.contains("mass"),
        "{err}"
    );
}
