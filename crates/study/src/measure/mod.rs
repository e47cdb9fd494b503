//! Outlet measurements on particle snapshots (physics.md §7).
