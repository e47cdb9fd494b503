//! Writers: atomic files, CSV, VTU/PVD, PNG/SVG plots and frames.
