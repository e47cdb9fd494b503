//! Clogging in a study (docs/physics.md §7.14): the mean avalanche size ⟨s⟩ against the
//! outlet size D/d, fitted by the critical divergence of Zuriguel et al. (2005) and by the
//! exponential growth of Thomas & Durian (2015), and set beside the published numbers.
//!
//! Everything is read from saved files: each case's `summary.json` (its `avalanches`
//! section, written by runs that break their arches, `[protocol.unclog]`), D and d from
//! `results.csv`. Cases are grouped by series and by dimension: a slab is quasi-2D (the
//! exponential then grows as exp(C D/d)), a silo 3D (exp(C (D/d)²)).

use std::collections::BTreeMap;
use std::path::Path;

use analysis::clogging::{compare_mean_size_fits, MeanSizeComparison, MeanSizePoint};
use analysis::Estimate;
use files::{AvalancheSummary, CaseStatus, ResultRow, StudyPaths, SUMMARY_FILE};

use super::Block;

/// Relative tolerance under which two D/d are the same grid value.
const OUTLET_TOLERANCE: f64 = 1e-9;

/// One case's avalanches as the section reads them.
#[derive(Debug, Clone, PartialEq)]
pub struct ClogCase {
    /// Series name.
    pub series: String,
    /// D/d [-].
    pub outlet: f64,
    /// Whether the container is 3D (a silo; a slab is quasi-2D).
    pub three_d: bool,
    /// The summary's avalanche section.
    pub avalanches: AvalancheSummary,
}

/// The avalanche sizes at one D/d, the replicas pooled.
#[derive(Debug, Clone, PartialEq)]
pub struct ClogRow {
    /// D/d [-].
    pub outlet: f64,
    /// Runs pooled [-].
    pub runs: usize,
    /// Avalanches ended by a clog, over the runs [-].
    pub avalanches: usize,
    /// ⟨s⟩ [grains] over the clog-ended avalanches of the runs, with its standard error.
    pub mean_size: Estimate,
    /// ⟨s⟩ [grains] with the avalanches cut short by a drained silo or the time limit
    /// counted as right-censored exponential sizes (docs/physics.md §7.14): every size of
    /// the runs over their clogs, its error itself over √n; `None` where a run's summary does
    /// not report it.
    pub mean_size_censored: Option<Estimate>,
    /// The decay size s_c [grains] of the size distribution's exponential tail, the runs'
    /// fits averaged with inverse-variance weights; `None` where no run had one.
    pub size_tail: Option<Estimate>,
    /// The time-lapse tail exponent α [-], likewise.
    pub lapse_tail: Option<Estimate>,
}

/// One series of one dimension: its rows and both fits.
#[derive(Debug, Clone, PartialEq)]
pub struct ClogGroup {
    /// Series name.
    pub series: String,
    /// Whether its containers are 3D.
    pub three_d: bool,
    /// Rows by D/d.
    pub rows: Vec<ClogRow>,
    /// Both fits of ⟨s⟩(D/d) and their comparison.
    pub fits: MeanSizeComparison,
}

/// Reads the avalanche section of every finished case of `rows` from its folder under `root`;
/// cases without one (no `[protocol.unclog]`) are left out.
pub fn load_clogging(root: &Path, rows: &[ResultRow]) -> Vec<ClogCase> {
    let paths = StudyPaths::new(root);
    rows.iter()
        .filter(|r| r.status != CaseStatus::Failed)
        .filter_map(|row| {
            let text = std::fs::read_to_string(paths.case_dir(&row.id).join(SUMMARY_FILE)).ok()?;
            let value: serde_json::Value = serde_json::from_str(&text).ok()?;
            let avalanches: AvalancheSummary =
                serde_json::from_value(value.get("avalanches")?.clone()).ok()?;
            // A slab has a thickness; a silo's is null.
            let three_d = value
                .get("thickness")
                .is_none_or(serde_json::Value::is_null);
            Some(ClogCase {
                series: row.series.clone(),
                outlet: row.outlet_width / row.particle_diameter,
                three_d,
                avalanches,
            })
        })
        .collect()
}

/// Inverse-variance mean of estimates with finite, positive errors; `None` for none.
fn weighted(values: impl Iterator<Item = (f64, f64)>) -> Option<Estimate> {
    let (mut sw, mut swx) = (0.0, 0.0);
    for (x, e) in values {
        if x.is_finite() && e.is_finite() && e > 0.0 {
            sw += 1.0 / (e * e);
            swx += x / (e * e);
        }
    }
    (sw > 0.0).then(|| Estimate::new(swx / sw, sw.sqrt().recip()))
}

/// The censored mean of pooled runs: each run's censored mean times its clogs is the sum of
/// all its sizes, so the pooled estimate is their total over all the clogs, with the
/// exponential law's error, itself over √n. `None` unless every run reports it.
fn pooled_censored(runs: &[&AvalancheSummary]) -> Option<Estimate> {
    let n: usize = runs.iter().map(|a| a.count).sum();
    if n == 0 || runs.iter().any(|a| !a.mean_size_censored.is_finite()) {
        return None;
    }
    let total: f64 = runs
        .iter()
        .map(|a| a.count as f64 * a.mean_size_censored)
        .sum();
    let mean = total / n as f64;
    Some(Estimate::new(mean, mean / (n as f64).sqrt()))
}

/// Pools the replicas of each D/d and fits each series. Two means are pooled: over the
/// clog-ended avalanches (each run's mean weighted by its count, its error from the runs'
/// errors carried to that weighted mean) and with the cut-short avalanches as censored sizes.
/// The fits take the censored mean where every run reports it (a finite silo that drains in a
/// long avalanche biases the clog-ended mean low), the clog-ended one otherwise.
pub fn analyse_clogging(cases: &[ClogCase]) -> Vec<ClogGroup> {
    let mut groups: BTreeMap<(String, bool), Vec<&ClogCase>> = BTreeMap::new();
    for c in cases {
        groups
            .entry((c.series.clone(), c.three_d))
            .or_default()
            .push(c);
    }
    groups
        .into_iter()
        .map(|((series, three_d), mut list)| {
            list.sort_by(|a, b| a.outlet.total_cmp(&b.outlet));
            let mut rows: Vec<ClogRow> = Vec::new();
            let mut k = 0;
            while k < list.len() {
                let r = list[k].outlet;
                let same: Vec<&ClogCase> = list[k..]
                    .iter()
                    .take_while(|c| (c.outlet - r).abs() <= OUTLET_TOLERANCE * r)
                    .copied()
                    .collect();
                k += same.len();
                let runs: Vec<&AvalancheSummary> = same
                    .iter()
                    .map(|c| &c.avalanches)
                    .filter(|a| a.count > 0 && a.mean_size.is_finite())
                    .collect();
                let n: usize = runs.iter().map(|a| a.count).sum();
                let mean_size = if n > 0 {
                    let total = n as f64;
                    let mean = runs
                        .iter()
                        .map(|a| a.count as f64 * a.mean_size)
                        .sum::<f64>()
                        / total;
                    let var = runs
                        .iter()
                        .map(|a| (a.count as f64 * a.mean_size_error).powi(2))
                        .sum::<f64>();
                    Estimate::new(mean, var.sqrt() / total)
                } else {
                    Estimate::new(f64::NAN, f64::NAN)
                };
                rows.push(ClogRow {
                    outlet: r,
                    runs: same.len(),
                    avalanches: n,
                    mean_size,
                    mean_size_censored: pooled_censored(&runs),
                    size_tail: weighted(
                        runs.iter()
                            .filter_map(|a| a.size_tail.map(|t| (t.value, t.error))),
                    ),
                    lapse_tail: weighted(
                        runs.iter()
                            .filter_map(|a| a.lapse_tail.map(|t| (t.value, t.error))),
                    ),
                });
            }
            let points: Vec<MeanSizePoint> = rows
                .iter()
                .map(|r| (r, r.mean_size_censored.unwrap_or(r.mean_size)))
                .filter(|(_, m)| m.value > 0.0 && m.standard_error > 0.0)
                .filter(|(r, _)| r.avalanches >= MIN_AVALANCHES)
                .map(|(r, m)| MeanSizePoint {
                    outlet: r.outlet,
                    mean_size: m,
                })
                .collect();
            let fits = compare_mean_size_fits(&points, if three_d { 2.0 } else { 1.0 });
            ClogGroup {
                series,
                three_d,
                rows,
                fits,
            }
        })
        .collect()
}

/// Fewest clog-ended avalanches at one D/d for its ⟨s⟩ to enter the fits: below it the
/// standard error of the mean is itself too uncertain to weight the point by.
const MIN_AVALANCHES: usize = 5;

/// "v ± e" with `digits` decimals (in powers of ten beyond 10⁶), or "–".
fn shown(e: Option<Estimate>, digits: usize) -> String {
    match e {
        Some(e) if e.value.is_finite() && e.value.abs() >= 1e6 => {
            format!("{:.3e} ± {:.1e}", e.value, e.standard_error)
        }
        Some(e) if e.value.is_finite() => {
            if e.standard_error.is_finite() {
                format!("{:.digits$} ± {:.digits$}", e.value, e.standard_error)
            } else {
                format!("{:.digits$}", e.value)
            }
        }
        _ => "–".into(),
    }
}

/// The published numbers the section compares with, and where each comes from.
pub const PUBLISHED: &str = "Published: Zuriguel et al., Phys. Rev. E 71, 051303 (2005), 3D silo of glass beads, arches broken by an air jet through the outlet: the avalanche sizes are exponentially distributed beyond the smallest, and ⟨s⟩ diverges as A (R_c − R)^(−γ) with R_c ≈ 4.94 and γ ≈ 6.9 (R = D/d). Janda et al., EPL 84, 44002 (2008) measured the same statistics in a 2D silo. Thomas & Durian, Phys. Rev. Lett. 114, 178001 (2015) argue that ⟨s⟩ grows as exp(C D^dim) without a critical outlet (dim = 2 in 3D, 1 in 2D); no number of theirs is quoted here. Zuriguel et al., Sci. Rep. 4, 7324 (2014): a flow clogs for good where the time lapses between grains have a tail t^(−α) with α ≤ 2 (their mean diverges); α > 2 means the flow always restarts.";

/// The section's blocks; none when no case broke its arches.
pub fn clogging_blocks(groups: &[ClogGroup]) -> Vec<Block> {
    let mut blocks = Vec::new();
    if groups.is_empty() {
        return blocks;
    }
    blocks.push(Block::Heading(
        2,
        "Clogging: avalanche sizes against D/d".into(),
    ));
    blocks.push(Block::Paragraph("Runs that break their arches ([protocol.unclog], docs/physics.md §5.11) cut their outlet crossings into avalanches at the clogs (avalanches.csv); ⟨s⟩: the mean size in grains over the avalanches a clog ended, with its standard error; ⟨s⟩ censored: the exponential law's maximum-likelihood mean with the avalanches cut short by a drained silo or the time limit counted as censored sizes (all sizes over the clogs, error itself over √n; docs/physics.md §7.14), which the fits take where every replica reports it. s_c: the decay size of the exponential tail P(s) ∝ exp(−s/s_c) above each run's median size (geometric maximum likelihood); α: the exponent of the time lapses between consecutive grains, P(t) ∝ t^(−α) above ten times each run's median lapse (continuous maximum likelihood); both averaged over the replicas with inverse-variance weights. Fits on ln⟨s⟩ weighted by σ_s/⟨s⟩: the critical divergence ⟨s⟩ = A (R_c − R)^(−γ) and the exponential ⟨s⟩ = B exp(C R^k), R = D/d; errors scaled by √(χ²/ν). ΔAIC = AIC(divergence) − AIC(exponential), AIC = χ² + 2p: below −2 favours the divergence, above 2 the exponential. Outlets with fewer than 5 avalanches are listed but left out of the fits; a divergence fit that ends on a bound of R_c or γ is reported as none found.".into()));
    for g in groups {
        let dim = if g.three_d { "3D" } else { "quasi-2D slab" };
        blocks.push(Block::Heading(3, format!("Series {} ({dim})", g.series)));
        let rows = g
            .rows
            .iter()
            .map(|r| {
                vec![
                    format!("{:.2}", r.outlet),
                    r.runs.to_string(),
                    r.avalanches.to_string(),
                    shown(Some(r.mean_size), 1),
                    shown(r.mean_size_censored, 1),
                    shown(r.size_tail, 1),
                    shown(r.lapse_tail, 2),
                ]
            })
            .collect();
        blocks.push(Block::Table {
            headers: vec![
                "D/d".into(),
                "runs".into(),
                "avalanches".into(),
                "⟨s⟩ [grains]".into(),
                "⟨s⟩ censored [grains]".into(),
                "s_c [grains]".into(),
                "α".into(),
            ],
            rows,
        });
        let k = if g.three_d { 2 } else { 1 };
        let mut fit_rows = Vec::new();
        match &g.fits.divergence {
            Some(f) => fit_rows.push(vec![
                "A (R_c − R)^(−γ)".into(),
                format!(
                    "A = {}, R_c = {}, γ = {}",
                    shown(Some(f.parameters[0]), 3),
                    shown(Some(f.parameters[1]), 2),
                    shown(Some(f.parameters[2]), 2)
                ),
                format!("{:.2}", f.reduced_chi_squared),
                format!("{:.1}", f.aic),
            ]),
            None => fit_rows.push(vec![
                "A (R_c − R)^(−γ)".into(),
                format!(
                    "not fitted: {}",
                    g.fits.divergence_error.clone().unwrap_or_default()
                ),
                "–".into(),
                "–".into(),
            ]),
        }
        let form = format!("B exp(C R^{k})");
        match &g.fits.exponential {
            Some(f) => fit_rows.push(vec![
                form,
                format!(
                    "B = {}, C = {}",
                    shown(Some(f.parameters[0]), 3),
                    shown(Some(f.parameters[1]), 4)
                ),
                format!("{:.2}", f.reduced_chi_squared),
                format!("{:.1}", f.aic),
            ]),
            None => fit_rows.push(vec![
                form,
                format!(
                    "not fitted: {}",
                    g.fits.exponential_error.clone().unwrap_or_default()
                ),
                "–".into(),
                "–".into(),
            ]),
        }
        blocks.push(Block::Table {
            headers: vec![
                "form".into(),
                "parameters".into(),
                "χ²/ν".into(),
                "AIC".into(),
            ],
            rows: fit_rows,
        });
        let verdict = match g.fits.aic_difference {
            d if d < -2.0 => format!("ΔAIC = {d:.1}: the data favour the critical divergence."),
            d if d > 2.0 => format!("ΔAIC = {d:.1}: the data favour the exponential growth."),
            d if d.is_finite() => format!(
                "ΔAIC = {d:.1}: the data do not tell the two forms apart; a divergence is \
                 only told from an exponential by outlets close to R_c, where avalanches are \
                 long."
            ),
            _ => "The two forms could not both be fitted, so they are not compared.".into(),
        };
        let against = match (&g.fits.divergence, g.three_d) {
            (Some(f), true) => format!(
                " Against Zuriguel et al. (2005, 3D glass beads): R_c = {} here against 4.94, γ = {} against 6.9.",
                shown(Some(f.parameters[1]), 2),
                shown(Some(f.parameters[2]), 2)
            ),
            (Some(f), false) => format!(
                " R_c = {} and γ = {} here; the 3D values of Zuriguel et al. (2005), R_c ≈ 4.94 and γ ≈ 6.9, do not apply to a slab one or two grains thick, whose 2D counterpart is Janda et al. (2008).",
                shown(Some(f.parameters[1]), 2),
                shown(Some(f.parameters[2]), 2)
            ),
            (None, _) => String::new(),
        };
        blocks.push(Block::Paragraph(format!("{verdict}{against}")));
    }
    blocks.push(Block::Paragraph(PUBLISHED.into()));
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;
    use files::TailFitSummary;

    fn case(series: &str, outlet: f64, count: usize, mean: f64, error: f64) -> ClogCase {
        ClogCase {
            series: series.into(),
            outlet,
            three_d: false,
            avalanches: AvalancheSummary {
                count,
                mean_size: mean,
                mean_size_error: error,
                mean_size_censored: f64::NAN,
                mean_size_censored_error: f64::NAN,
                mean_mass: f64::NAN,
                mean_duration: f64::NAN,
                mean_arrest: f64::NAN,
                pulses: count,
                failed_pulses: 0,
                size_tail: Some(TailFitSummary {
                    threshold: 1.0,
                    samples: 20,
                    value: mean,
                    error,
                }),
                lapse_tail: None,
            },
        }
    }

    #[test]
    fn replicas_pool_by_their_counts_and_each_series_is_fitted() {
        // Two replicas at D/d = 2 (10 avalanches of mean 4 ± 1, 30 of mean 8 ± 1): the
        // pooled mean is (40 + 240)/40 = 7, its error √(10² + 30²)/40. Then three more
        // outlets on ⟨s⟩ = exp(R), so the slab's exponential C is 1 within its error.
        let cases = vec![
            case("s", 2.0, 10, 4.0, 1.0),
            case("s", 2.0, 30, 8.0, 1.0),
            case("s", 3.0, 20, 3f64.exp(), 0.1 * 3f64.exp()),
            case("s", 4.0, 20, 4f64.exp(), 0.1 * 4f64.exp()),
            case("s", 5.0, 20, 5f64.exp(), 0.1 * 5f64.exp()),
        ];
        let groups = analyse_clogging(&cases);
        assert_eq!(groups.len(), 1);
        let first = &groups[0].rows[0];
        assert_eq!((first.runs, first.avalanches), (2, 40));
        // Exact arithmetic of the pooling, to rounding.
        assert!((first.mean_size.value - 7.0).abs() < 1e-12);
        assert!((first.mean_size.standard_error - 1000f64.sqrt() / 40.0).abs() < 1e-12);
        let fit = groups[0].fits.exponential.as_ref().expect("fitted");
        // C near 1: the first point, 7 against e², pulls it; 0.2 is several errors wide.
        assert!((fit.parameters[1].value - 1.0).abs() < 0.2, "{fit:?}");
        let blocks = clogging_blocks(&groups);
        let text = format!("{blocks:?}");
        assert!(
            text.contains("B exp(C R^1)") && text.contains("4.94"),
            "{text}"
        );
        assert!(clogging_blocks(&[]).is_empty());
    }

    #[test]
    fn censored_means_pool_over_all_clogs_and_enter_the_fits() {
        // Each case's clog-ended mean is half its censored mean, as when long avalanches
        // drain the silo; the censored means follow exp(R) exactly, so the exponential fit
        // recovers B = 1 from them and would give B = 1/2 from the clog-ended ones.
        let censored = |outlet: f64, count: usize, mean: f64| {
            let mut c = case("s", outlet, count, 0.5 * mean, 0.05 * mean);
            c.avalanches.mean_size_censored = mean;
            c.avalanches.mean_size_censored_error = mean / (count as f64).sqrt();
            c
        };
        let e2 = 2f64.exp();
        let cases = vec![
            censored(2.0, 4, 0.5 * e2),
            censored(2.0, 12, 7.0 / 6.0 * e2),
            censored(3.0, 16, 3f64.exp()),
            censored(4.0, 16, 4f64.exp()),
            censored(5.0, 16, 5f64.exp()),
        ];
        let groups = analyse_clogging(&cases);
        let first = groups[0].rows[0]
            .mean_size_censored
            .expect("every run reports it");
        // Pooled over the 16 clogs: (4 · e²/2 + 12 · 7e²/6)/16 = e², error e²/4; exact to
        // rounding.
        assert!((first.value - e2).abs() < 1e-12 * e2, "{first:?}");
        assert!((first.standard_error - e2 / 4.0).abs() < 1e-12 * e2);
        let fit = groups[0].fits.exponential.as_ref().expect("fitted");
        // Points on B exp(C R) with B = 1, C = 1: the fit is exact to its solver's tolerance;
        // 0.05 tells B = 1 from the clog-ended B = 0.5 by far.
        assert!((fit.parameters[0].value - 1.0).abs() < 0.05, "{fit:?}");
        assert!((fit.parameters[1].value - 1.0).abs() < 0.05, "{fit:?}");
        // A run without the censored mean (an older summary) leaves its row without one.
        let mut old = cases.clone();
        old[0].avalanches.mean_size_censored = f64::NAN;
        assert!(analyse_clogging(&old)[0].rows[0]
            .mean_size_censored
            .is_none());
    }
}
