//! The outflow composition of a mixture over time, `composition.csv`: per W(t) bin, the mass
//! and number of each component whose centre crossed the outlet, and its share of the bin's
//! mass. The crossing events carry each particle's id, and the run state keeps each id's
//! component (`RunState::components`), so the table is derived after the run from what a
//! checkpoint holds.

use files::Cell;
use measure::CrossingEvent;

/// A component index no particle has: an id the run never recorded (not expected).
const UNKNOWN: u8 = u8::MAX;

/// The columns of `composition.csv` for components named `names`:
///
/// | column | unit | what |
/// |---|---|---|
/// | `time_s` | s | bin centre, from the gate's opening (the `time` of `flow.csv`) |
/// | `mass_kg` | kg | mass of every crossing in the bin (`rate` × bin width in `flow.csv`) |
/// | `count` | - | crossings in the bin |
/// | `NAME_mass_kg` | kg | mass of component NAME's crossings in the bin |
/// | `NAME_count` | - | component NAME's crossings in the bin |
/// | `NAME_mass_fraction` | - | `NAME_mass_kg` / `mass_kg`, in [0, 1]; NaN for a bin nothing crossed |
pub(crate) fn composition_columns(names: &[String]) -> Vec<String> {
    let mut columns = vec!["time_s".to_string(), "mass_kg".into(), "count".into()];
    for name in names {
        columns.push(format!("{name}_mass_kg"));
        columns.push(format!("{name}_count"));
        columns.push(format!("{name}_mass_fraction"));
    }
    columns
}

/// The rows of `composition.csv`: the bins of W(t) over [0, max(`end`, `bin_width`)) from
/// the gate's opening at `opened` [s], a trailing partial bin dropped, each event in the bin
/// ⌊(t − opened)/Δt⌋, exactly as `RateSeries::from_events` bins `flow.csv`. Each bin's mass
/// is summed in event order, as there, so `mass_kg` is the very sum that `flow.csv`'s rate
/// divides by the bin width; the components' masses are summed in the same order, so they
/// add up to `mass_kg` within rounding. `components` gives each particle's component by id.
pub(crate) fn composition_rows(
    events: &[CrossingEvent],
    opened: f64,
    end: f64,
    bin_width: f64,
    components: &[u8],
    names: &[String],
) -> Vec<Vec<Cell>> {
    let end = end.max(bin_width);
    let bins = (end / bin_width).floor().max(0.0) as usize;
    let n = names.len();
    let mut total = vec![(0.0, 0u64); bins];
    let mut by_component = vec![(0.0, 0u64); bins * n];
    for e in events {
        let index = ((e.time - opened) / bin_width).floor();
        if !(index >= 0.0 && (index as usize) < bins) {
            continue;
        }
        let k = index as usize;
        total[k].0 += e.mass;
        total[k].1 += 1;
        let c = components.get(e.id as usize).copied().unwrap_or(UNKNOWN) as usize;
        if c < n {
            by_component[k * n + c].0 += e.mass;
            by_component[k * n + c].1 += 1;
        }
    }
    (0..bins)
        .map(|k| {
            let (mass, count) = total[k];
            let mut row: Vec<Cell> = vec![
                ((k as f64 + 0.5) * bin_width).into(),
                mass.into(),
                (count as f64).into(),
            ];
            for &(m, c) in &by_component[k * n..(k + 1) * n] {
                let fraction = if mass > 0.0 { m / mass } else { f64::NAN };
                row.extend([m.into(), (c as f64).into(), fraction.into()]);
            }
            row
        })
        .collect()
}
