//! What the report tests that write fake studies share: a folder of their own and the
//! header of results.csv.

use std::path::PathBuf;

/// A folder named after the test and the process under the system's temporary directory,
/// emptied when made and removed on drop.
pub struct Folder(pub PathBuf);

impl Folder {
    pub fn new(name: &str) -> Self {
        let path =
            std::env::temp_dir().join(format!("hopperflow-report-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).unwrap();
        Self(path)
    }
}

impl Drop for Folder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The 26 columns of `results.csv`, as a study writes them, with the line's end.
pub const RESULTS_HEADER: &str =
    "id,series,replica,labels,outlet_width,hopper_angle_deg,outlet_gap,dimensionless_gap,\
     thickness,wall_friction,width,particle_diameter,particle_density,particles,seed,\
     discharge_rate,discharge_rate_error,centre_velocity,centre_area_fraction,\
     max_area_fraction,bulk_volume_fraction,flux_check_rate,flux_check_ratio,\
     plateau_found,clogged,status\n";
