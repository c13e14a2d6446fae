//! Every figure of the paper's job, checked as a referee would look at it.

use lgsvi_experiments::ExperimentError;
use lgsvi_plot::{inspect, layout, legend_labels, legend_text_width, Figure, LEGEND_TEXT_X, SIZE};
use lgsvi_reports::reproduce::{Artifact, PaperSubjects};

/// What is drawn for each series spans exactly its data (no renderer-made spikes, nothing
/// cut), the data's extremes are numbers of the figure's CSV, the legend and the title fit
/// in their own areas (the legend beside the plot, never over the data), and failed runs
/// are marked rather than dropped.
#[test]
fn every_figure_draws_its_data_and_nothing_else() {
    let mut figures: Vec<(String, Figure, String)> = Vec::new();
    let mut emit = |artifact: Artifact<'_>| -> Result<(), ExperimentError> {
        if let Artifact::Figure { name, figure, csv } = artifact {
            figures.push((name.to_string(), figure.clone(), csv.to_string()));
        }
        Ok(())
    };
    PaperSubjects::new()
        .unwrap()
        .job(&mut emit, &mut ())
        .unwrap();
    assert_eq!(figures.len(), 8, "the nine figures less the 3D sphere");
    for (name, fig, csv) in &figures {
        let cells: Vec<f64> = csv
            .lines()
            .skip(1)
            .flat_map(|l| l.split(',').filter_map(|c| c.parse::<f64>().ok()))
            .collect();
        for drawn in inspect(fig) {
            assert_eq!(drawn.drawn, drawn.data, "{name} / {}", drawn.label);
            let series = fig.series.iter().find(|s| s.label == drawn.label).unwrap();
            // The data's own extremes (before zeros go to a log axis's bottom edge).
            let finite = || series.points.iter().map(|p| p.1).filter(|y| y.is_finite());
            let lo = finite().fold(f64::INFINITY, f64::min);
            let hi = finite().fold(f64::NEG_INFINITY, f64::max);
            for v in [lo, hi].into_iter().filter(|v| v.is_finite() && *v != 0.0) {
                assert!(
                    cells.contains(&v),
                    "{name} / {}: plotted extreme {v:e} is not in the CSV",
                    drawn.label
                );
            }
            let failed = series.points.iter().filter(|p| !p.1.is_finite()).count();
            assert_eq!(drawn.failures, failed, "{name}: every failure is marked");
        }
        let layout = layout(fig, SIZE);
        let (p, l) = (layout.plot, layout.legend);
        assert!(
            p.2 <= l.0,
            "{name}: the legend is beside the plot, not over it"
        );
        // Text widths are the font's metrics; renderers differ by a few pixels, so a
        // label must leave 12 px before the edge.
        for label in legend_labels(fig) {
            let width = legend_text_width(&label);
            assert!(
                l.0 + LEGEND_TEXT_X + width as i32 + 12 <= l.2,
                "{name}: legend label {label:?} is cut"
            );
        }
        assert!(layout.title_fits, "{name}: title cut");
    }
}
