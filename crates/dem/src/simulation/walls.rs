//! Walls in motion and the loads on them: prescribed rigid motions advanced every step
//! (docs/physics.md §5.4), each wall's total force and torque of the last step, and the
//! element loads of curved and meshed walls summed over a window (§5.5).

use glam::DQuat;

use super::*;
use crate::forces::loads::{load_of, SurfaceLoads, WallLoad};
use crate::wall::geometry::SurfaceElements;
use crate::wall::WallMotion;

impl Simulation {
    /// Sets how a wall moves: its velocity, its angular velocity about a centre, and whether
    /// each step displaces it ([`WallMotion`]). The contact law sees v + ω × (x − c).
    pub fn set_wall_motion(&mut self, id: WallId, motion: WallMotion) -> Result<(), DemError> {
        self.wall_mut(id)?
            .set_motion(motion)
            .map_err(|e| DemError::InvalidInput(format!("wall {}: {e}", id.0)))
    }

    /// Turns a wall rigidly by `rotation` about the point `centre` [m] (between steps).
    pub fn rotate_wall(
        &mut self,
        id: WallId,
        centre: DVec3,
        rotation: DQuat,
    ) -> Result<(), DemError> {
        if !(centre.is_finite() && rotation.is_finite() && rotation.length() > 0.0) {
            return Err(DemError::InvalidInput(format!(
                "wall {}: rotation centre must be finite and the rotation a finite non-zero \
                 quaternion, got {centre} and {rotation}",
                id.0
            )));
        }
        let reach = self.farthest_particle_from(centre);
        let wall = self.wall_mut(id)?;
        wall.rotate_about(centre, rotation.normalize());
        let angle = rotation.normalize().to_axis_angle().1.abs();
        self.state.wall_drift += angle.min(std::f64::consts::PI) * reach;
        Ok(())
    }

    /// The load on a wall in the last step: the force and the torque about the origin the
    /// particles exerted on it [N, N m]; zero for a wall that does not sum its load
    /// ([`Wall::sums_load`]).
    pub fn wall_load(&self, id: WallId) -> Result<WallLoad, DemError> {
        self.wall(id).ok_or(DemError::UnknownWall(id.0))?;
        Ok(self
            .wall_loads
            .get(id.0 as usize)
            .copied()
            .unwrap_or_default())
    }

    /// Sets the number of bands of equal length along a cylinder's or cone's axis its
    /// element loads are booked in (1 at first). Refused for other shapes: a mesh books
    /// to its triangles, a plane or polygon has only its total load.
    pub fn set_wall_bands(&mut self, id: WallId, bands: usize) -> Result<(), DemError> {
        let wall = self.wall(id).ok_or(DemError::UnknownWall(id.0))?;
        if wall.shape().elements() != SurfaceElements::Bands || bands == 0 {
            return Err(DemError::InvalidInput(format!(
                "wall {}: bands are set for a cylinder or cone only, and at least 1, got {bands}",
                id.0
            )));
        }
        let loads = &mut self.state.surface_loads[id.0 as usize];
        *loads = SurfaceLoads {
            duration: 0.0,
            elements: vec![Default::default(); bands],
        };
        Ok(())
    }

    /// The element loads of a curved or meshed wall summed since the window began (the
    /// wall's addition or the last [`Simulation::take_surface_loads`]): one entry per
    /// triangle of a mesh or band of a cylinder or cone; none for a plane or polygon.
    pub fn surface_loads(&self, id: WallId) -> Result<&SurfaceLoads, DemError> {
        self.wall(id).ok_or(DemError::UnknownWall(id.0))?;
        Ok(&self.state.surface_loads[id.0 as usize])
    }

    /// The element loads of a wall, as [`Simulation::surface_loads`], and a new window.
    pub fn take_surface_loads(&mut self, id: WallId) -> Result<SurfaceLoads, DemError> {
        self.wall(id).ok_or(DemError::UnknownWall(id.0))?;
        let loads = &mut self.state.surface_loads[id.0 as usize];
        let fresh = SurfaceLoads {
            duration: 0.0,
            elements: vec![Default::default(); loads.elements.len()],
        };
        Ok(std::mem::replace(loads, fresh))
    }

    /// The element loads a new wall starts with: one per triangle of a mesh, one band of a
    /// cylinder or cone, none otherwise.
    pub(super) fn fresh_surface_loads(wall: &Wall) -> SurfaceLoads {
        let elements = match wall.shape().elements() {
            SurfaceElements::None => 0,
            SurfaceElements::Triangles(n) => n,
            SurfaceElements::Bands => 1,
        };
        SurfaceLoads {
            duration: 0.0,
            elements: vec![Default::default(); elements],
        }
    }

    /// Advances every displaced wall by its motion over `dt` [s]: a translation v dt and a
    /// turn ω dt about its centre, which moves with it; and books how far the wall's points
    /// near the particles may have moved, for the list-build test.
    pub(super) fn move_walls(&mut self, dt: f64) {
        let moving: Vec<(usize, WallMotion)> = self
            .state
            .walls
            .iter()
            .enumerate()
            .filter_map(|(w, wall)| Some((w, wall.as_ref()?.motion())))
            .filter(|(_, m)| {
                m.displaced && (m.velocity != DVec3::ZERO || m.angular_velocity != DVec3::ZERO)
            })
            .collect();
        for (w, m) in moving {
            let turn = m.angular_velocity * dt;
            let reach = if turn == DVec3::ZERO {
                0.0
            } else {
                self.farthest_particle_from(m.centre)
            };
            let wall = self.state.walls[w].as_mut().expect("a present wall");
            if m.velocity != DVec3::ZERO {
                wall.translate(m.velocity * dt);
            }
            if turn != DVec3::ZERO {
                // The centre has moved with the wall: turn about where it is now.
                let centre = wall.centre;
                wall.rotate_about(centre, DQuat::from_scaled_axis(turn));
            }
            self.state.wall_drift += m.velocity.length() * dt + turn.length() * reach;
        }
    }

    /// The largest distance of a particle from `point` [m], plus the skin: how far from a
    /// turning wall's centre its contacts can lie.
    fn farthest_particle_from(&self, point: DVec3) -> f64 {
        let p = &self.state.particles;
        let far = p
            .position
            .iter()
            .zip(&p.radius)
            .map(|(x, r)| x.distance(point) + r)
            .fold(0.0, f64::max);
        far + self.state.skin
    }

    /// The load on a wall integrated over time since it was added: force [N s] and torque
    /// about the origin [N m s], summed step by step. A window's mean load is the difference
    /// of two readings over the time between them, so a caller needs to look only at the
    /// window's ends, not at every step.
    pub fn wall_impulse(&self, id: WallId) -> Result<WallLoad, DemError> {
        self.wall(id).ok_or(DemError::UnknownWall(id.0))?;
        Ok(self
            .state
            .wall_impulses
            .get(id.0 as usize)
            .copied()
            .unwrap_or_default())
    }

    /// Keeps the last evaluation's wall loads, adds them to the walls' impulses and the step
    /// to the element windows.
    pub(super) fn keep_wall_loads(&mut self, dt: f64) {
        let q = self.load_quanta;
        self.wall_loads.clear();
        self.wall_loads
            .extend(self.buffers.loads.iter().map(|sum| load_of(sum, &q)));
        let impulses = &mut self.state.wall_impulses;
        impulses.resize(self.wall_loads.len(), WallLoad::default());
        for (i, l) in impulses.iter_mut().zip(&self.wall_loads) {
            i.force += l.force * dt;
            i.torque += l.torque * dt;
        }
        for loads in &mut self.state.surface_loads {
            if !loads.elements.is_empty() {
                loads.duration += dt;
            }
        }
    }
}
