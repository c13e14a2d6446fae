//! The Newton iteration's work, pinned: for each case × chart × matching × (h, n), the
//! iterations, the largest count in one step, the factorisations and the redone steps of a
//! fixed run, against the committed table `tests/data/newton_statistics.txt`. A change that
//! loses convergence (more iterations, more factorisations, a fallback that now fires)
//! fails here even when the results stay within their tolerances.
//!
//! The counts are deterministic for a build on a given machine (same arithmetic, same
//! order). After a change that alters them on purpose, regenerate the table with
//! `LGSVI_BLESS=1 cargo test --release -p lgsvi-tests --test newton_statistics` and say why
//! in the commit.

mod common;

use lgsvi_lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::group::{GroupChart, Screw};
use lgsvi_mechanics::integrator::Statistics;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{
    FreeBody, Inertia, Integrator, Matching, MechanicsError, OrbitingBody, StepSettings, System,
};
use nalgebra::SVector;

const TABLE: &str = "data/newton_statistics.txt";

/// One line per run: `case chart matching h n steps: iterations max factorizations rejected`.
fn measured() -> String {
    let mut out = String::from(
        "# case chart matching h n steps: newton_iterations max_per_step factorizations rejected_steps\n",
    );
    for name in ["A", "B", "C"] {
        let case = common::case(name);
        for chart in [ChartKind::Exp, ChartKind::Cayley, ChartKind::CayleyUnscaled] {
            for matching in [Matching::Exact, Matching::Paper] {
                for (h, n, steps) in [(0.5, 4, 40), (0.5, 8, 40), (1.0, 12, 20), (0.25, 16, 40)] {
                    let settings = StepSettings::new(h, n)
                        .unwrap()
                        .with_chart(chart)
                        .with_matching(matching);
                    let line = match common::run(&case, settings, steps, steps) {
                        Ok((_, s)) => format!(
                            "{} {} {} {}",
                            s.newton_iterations,
                            s.max_newton_iterations,
                            s.factorizations,
                            s.rejected_steps
                        ),
                        Err(e) => format!("failed: {e}"),
                    };
                    out.push_str(&format!(
                        "{name} {chart} {matching:?} {h} {n} {steps}: {line}\n"
                    ));
                }
            }
        }
    }
    // The bodies in space (the orbiting body O1, and a free body with its inertia and
    // start), in the rotation–translation chart and SE(3)'s screw chart: the closed forms
    // and the predictor in the chart decide their work.
    let o1 = lgsvi_cases::case("O1").unwrap();
    let inertia = Inertia::from_principal_moments(o1.principal_moments().unwrap()).unwrap();
    let orbit = OrbitingBody::new(inertia, o1.mass.unwrap(), o1.mu.unwrap()).unwrap();
    let free = FreeBody::new(inertia, o1.mass.unwrap()).unwrap();
    let start = SE3::new(SO3::identity(), o1.position0.unwrap());
    let (w0, v0) = (o1.omega0, o1.velocity0.unwrap());
    let xi = SVector::<f64, 6>::new(w0.x, w0.y, w0.z, v0.x, v0.y, v0.z);
    for (h, n, steps) in [(0.5, 8, 40), (2.0, 8, 10), (5.0, 12, 4)] {
        let settings = StepSettings::new(h, n).unwrap();
        let screw = Screw(ChartKind::Exp);
        let lines = [
            (
                "O1",
                "exp",
                line(Integrator::new(orbit, settings, start, xi), steps),
            ),
            (
                "O1-free",
                "exp",
                line(Integrator::new(free, settings, start, xi), steps),
            ),
            (
                "O1",
                "screw(exp)",
                line(
                    Integrator::with_chart(orbit, screw, settings, start, xi),
                    steps,
                ),
            ),
            (
                "O1-free",
                "screw(exp)",
                line(
                    Integrator::with_chart(free, screw, settings, start, xi),
                    steps,
                ),
            ),
        ];
        for (name, chart, work) in lines {
            out.push_str(&format!("{name} {chart} Exact {h} {n} {steps}: {work}\n"));
        }
    }
    out
}

/// `iterations max factorizations rejected` of `steps` steps of `integrator`, or why it
/// failed.
fn line<S, C>(integrator: Result<Integrator<S, C, 6>, MechanicsError>, steps: usize) -> String
where
    S: System<6>,
    C: GroupChart<S::Group, 6>,
{
    let run = || -> Result<Statistics, MechanicsError> {
        let mut it = integrator?;
        it.run(steps, steps)?;
        Ok(*it.statistics())
    };
    match run() {
        Ok(s) => format!(
            "{} {} {} {}",
            s.newton_iterations, s.max_newton_iterations, s.factorizations, s.rejected_steps
        ),
        Err(e) => format!("failed: {e}"),
    }
}

#[test]
fn newton_work_is_what_the_table_pins() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(TABLE);
    let now = measured();
    if std::env::var_os("LGSVI_BLESS").is_some() {
        std::fs::write(&path, &now).unwrap();
        return;
    }
    let pinned = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (LGSVI_BLESS=1 writes it)", path.display()));
    let differences: Vec<String> = pinned
        .lines()
        .zip(now.lines())
        .filter(|(a, b)| a != b)
        .map(|(a, b)| format!("pinned  {a}\nmeasured {b}"))
        .collect();
    assert!(
        differences.is_empty() && pinned.lines().count() == now.lines().count(),
        "the Newton iteration's work changed:\n{}",
        differences.join("\n")
    );
}
