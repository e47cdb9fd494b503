//! Changes to the system between steps: materials and their interactions, particles added
//! and removed, walls added, moved and removed and their interactions per particle material;
//! and the preparation (mixed coefficients, the Δt check) that runs before the next step
//! whenever one of them changed the set-up.

use super::*;

/// A particle taken out of the simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RemovedParticle {
    /// Its tag.
    pub tag: ParticleTag,
    /// Position when removed [m].
    pub position: DVec3,
    /// Velocity when removed [m/s].
    pub velocity: DVec3,
    /// Mass [kg].
    pub mass: f64,
}

pub(super) fn check_interaction(i: &Interaction) -> Result<(), DemError> {
    let ok = i.friction >= 0.0
        && i.rolling_friction >= 0.0
        && i.restitution > 0.0
        && i.restitution <= 1.0
        && i.friction.is_finite()
        && i.rolling_friction.is_finite();
    if ok {
        Ok(())
    } else {
        Err(DemError::InvalidInput(format!(
            "friction ≥ 0, rolling friction ≥ 0 and restitution in (0, 1] required, got {i:?}"
        )))
    }
}

/// Refuses a material with a density or Young's modulus that is not positive and finite, or
/// a Poisson's ratio outside (−1, 0.5).
pub(super) fn check_material(material: &Material) -> Result<(), DemError> {
    let fault = if !(material.density > 0.0 && material.density.is_finite()) {
        Some((
            "density",
            material.density,
            "must be positive and finite [kg/m³]",
        ))
    } else if !(material.youngs_modulus > 0.0 && material.youngs_modulus.is_finite()) {
        Some((
            "Young's modulus",
            material.youngs_modulus,
            "must be positive and finite [Pa]",
        ))
    } else if !(material.poisson_ratio > -1.0 && material.poisson_ratio < 0.5) {
        Some((
            "Poisson ratio",
            material.poisson_ratio,
            "must be in (-1, 0.5)",
        ))
    } else {
        None
    };
    match fault {
        Some((what, value, range)) => Err(DemError::InvalidInput(format!(
            "unphysical material: {what} {value} {range}; got {material:?}"
        ))),
        None => Ok(()),
    }
}

/// Refuses a material id beyond the `registered` materials.
fn check_material_id(id: MaterialId, registered: usize) -> Result<(), DemError> {
    if (id.0 as usize) < registered {
        Ok(())
    } else {
        Err(DemError::InvalidInput(format!(
            "unknown material {}: {registered} material(s) are registered",
            id.0
        )))
    }
}

impl Simulation {
    /// Registers a material and how it interacts with itself.
    pub fn add_material(
        &mut self,
        material: Material,
        self_interaction: Interaction,
    ) -> Result<MaterialId, DemError> {
        check_material(&material)?;
        check_interaction(&self_interaction)?;
        let s = &mut self.state;
        let old = s.materials.len();
        let n = old + 1;
        let mut table = vec![None; n * n];
        for a in 0..old {
            for b in 0..old {
                table[a * n + b] = s.interactions[a * old + b];
            }
        }
        table[old * n + old] = Some(self_interaction);
        s.materials.push(material);
        s.interactions = table;
        self.unprepare();
        Ok(MaterialId(old as u16))
    }

    /// Sets how two different materials interact.
    pub fn set_interaction(
        &mut self,
        a: MaterialId,
        b: MaterialId,
        interaction: Interaction,
    ) -> Result<(), DemError> {
        check_interaction(&interaction)?;
        let n = self.state.materials.len();
        check_material_id(a, n)?;
        check_material_id(b, n)?;
        self.state.interactions[a.0 as usize * n + b.0 as usize] = Some(interaction);
        self.state.interactions[b.0 as usize * n + a.0 as usize] = Some(interaction);
        self.unprepare();
        Ok(())
    }

    /// Makes room for `additional` more particles at once, so that adding a known number of
    /// them allocates each array once, to its size, instead of doubling it on the way
    /// (up to twice the memory the particles need). Changes nothing else.
    pub fn reserve_particles(&mut self, additional: usize) {
        self.state.particles.reserve_exact(additional);
    }

    /// Adds a particle; its initial force is its weight.
    pub fn add_particle(&mut self, init: ParticleInit) -> Result<ParticleTag, DemError> {
        check_material_id(init.material, self.state.materials.len())?;
        let mat = &self.state.materials[init.material.0 as usize];
        if !(init.radius > 0.0 && init.radius.is_finite())
            || !init.position.is_finite()
            || !init.velocity.is_finite()
            || !init.angular_velocity.is_finite()
        {
            return Err(DemError::InvalidInput(format!(
                "particle radius must be positive and the state finite: {init:?}"
            )));
        }
        let density = mat.density;
        let g = self.state.config.gravity;
        let p = &mut self.state.particles;
        let tag = p.push(&init, density);
        let k = p.len() - 1;
        p.force[k] = p.mass[k] * g;
        self.state.needs_rebuild = true;
        self.unprepare();
        Ok(tag)
    }

    /// Adds a rigid clump of `shape` (docs/physics.md §11) of `material`: the shape's frame
    /// turned by `orientation` and its centre of mass put at `position` [m], moving at
    /// `velocity` [m/s] and spinning at `angular_velocity` [rad/s] (world frame). Its members
    /// become particles flagged [`crate::FLAG_CLUMP_MEMBER`], each carrying the clump's mass
    /// for its contact laws. Returns the clump's index among [`Simulation::clumps`].
    pub fn add_clump(
        &mut self,
        shape: &ClumpShape,
        material: MaterialId,
        placement: (DVec3, DQuat),
        motion: (DVec3, DVec3),
    ) -> Result<usize, DemError> {
        self.add_scaled_clump((shape, 1.0), material, placement, motion)
    }

    /// [`Simulation::add_clump`] of `shape` scaled by `scale` (> 0) about its members' frame
    /// ([`crate::clump::ClumpBody::scaled`]): a grain of a size distribution, made from one
    /// body per shape instead of integrating each grain's union anew.
    pub fn add_scaled_clump(
        &mut self,
        (shape, scale): (&ClumpShape, f64),
        material: MaterialId,
        (position, orientation): (DVec3, DQuat),
        (velocity, angular_velocity): (DVec3, DVec3),
    ) -> Result<usize, DemError> {
        check_material_id(material, self.state.materials.len())?;
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(DemError::InvalidInput(format!(
                "a clump's scale must be finite and greater than 0: {scale}"
            )));
        }
        if !(position.is_finite()
            && orientation.is_finite()
            && velocity.is_finite()
            && angular_velocity.is_finite())
            || !(orientation.length() > 0.0)
        {
            return Err(DemError::InvalidInput(format!(
                "a clump's position, orientation and motion must be finite, the orientation \
                 non-zero: {position}, {orientation}, {velocity}, {angular_velocity}"
            )));
        }
        let density = self.state.materials[material.0 as usize].density;
        let s = &mut self.state;
        let shape_index = s.clumps.shape_index(shape, density, scale);
        let body = &s.clumps.shapes[shape_index];
        let q = (orientation.normalize() * body.axes).normalize();
        let inertia = body.principal_inertia;
        let momentum = q * (inertia * (q.inverse() * angular_velocity));
        let w = crate::clump::rotation::angular_velocity(q, momentum, inertia);
        let g = s.config.gravity;
        let weight = body.mass * g;
        let c = s.clumps.len();
        let p = &mut s.particles;
        let mut first = None;
        for &(offset, radius) in &body.members {
            let arm = q * offset;
            let init = ParticleInit {
                position: position + arm,
                velocity: velocity + w.cross(arm),
                angular_velocity: w,
                radius,
                material,
                flags: crate::particles::FLAG_CLUMP_MEMBER,
            };
            let tag = p.push(&init, density);
            first.get_or_insert(tag);
            let k = p.len() - 1;
            // The member's contact laws see the whole grain's mass.
            p.mass[k] = body.mass;
            p.inertia[k] = 0.4 * body.mass * radius * radius;
            p.inv_mass[k] = 1.0 / body.mass;
            p.inv_inertia[k] = 1.0 / p.inertia[k];
            p.force[k] = body.mass * g;
            p.clump[k] = c as u32;
        }
        let cl = &mut s.clumps;
        cl.shape.push(shape_index as u32);
        cl.first_tag.push(first.unwrap_or_default());
        cl.position.push(position);
        cl.velocity.push(velocity);
        cl.orientation.push(q);
        cl.momentum.push(momentum);
        cl.force.push(weight);
        cl.torque.push(DVec3::ZERO);
        s.needs_rebuild = true;
        self.unprepare();
        Ok(c)
    }

    /// Removes every body whose centre satisfies `remove` (a free sphere's centre, a clump's
    /// centre of mass) and returns them, one entry per body as
    /// [`Simulation::remove_particles`] gives them. What leaves a silo is counted by where a
    /// grain's mass is, whatever its shape.
    pub fn remove_bodies(&mut self, mut remove: impl FnMut(DVec3) -> bool) -> Vec<RemovedParticle> {
        let gone: Vec<bool> = self
            .state
            .clumps
            .position
            .iter()
            .map(|&x| remove(x))
            .collect();
        self.remove_particles(|k, p| match p.clump[k] {
            crate::particles::NO_CLUMP => remove(p.position[k]),
            c => gone[c as usize],
        })
    }

    /// Removes every particle for which `remove(index, particles)` is true and returns the
    /// bodies removed. A clump goes whole: when one of its members is to go, all of them go,
    /// and the clump. The list holds one entry per body, in the particles' order: a free
    /// sphere as it was, a clump where its first member was, as its first member's tag,
    /// its centre of mass, its velocity and its whole mass (its members carry the clump's
    /// mass for their contact laws, so a sum over members would count it once a member).
    pub fn remove_particles(
        &mut self,
        mut remove: impl FnMut(usize, &ParticleSet) -> bool,
    ) -> Vec<RemovedParticle> {
        let p = &self.state.particles;
        let mut keep: Vec<bool> = (0..p.len()).map(|k| !remove(k, p)).collect();
        if keep.iter().all(|&k| k) {
            return Vec::new();
        }
        let mut gone = vec![false; self.state.clumps.len()];
        for (k, &c) in p.clump.iter().enumerate() {
            if c != crate::particles::NO_CLUMP && !keep[k] {
                gone[c as usize] = true;
            }
        }
        for (k, &c) in p.clump.iter().enumerate() {
            if c != crate::particles::NO_CLUMP && gone[c as usize] {
                keep[k] = false;
            }
        }
        let clumps = &self.state.clumps;
        let removed = (0..p.len())
            .filter(|&k| !keep[k])
            .filter_map(|k| match p.clump[k] {
                crate::particles::NO_CLUMP => Some(RemovedParticle {
                    tag: p.tag[k],
                    position: p.position[k],
                    velocity: p.velocity[k],
                    mass: p.mass[k],
                }),
                c => {
                    let c = c as usize;
                    (p.tag[k] == clumps.first_tag[c]).then(|| RemovedParticle {
                        tag: clumps.first_tag[c],
                        position: clumps.position[c],
                        velocity: clumps.velocity[c],
                        mass: clumps.body(c).mass,
                    })
                }
            })
            .collect();
        // The survivors' contact memory follows them across the change of indices: new
        // body k was body `origin[k]`.
        let origin: Vec<u32> = (0..keep.len() as u32)
            .filter(|&k| keep[k as usize])
            .collect();
        self.state.particles.retain_mask(&keep);
        if gone.contains(&true) {
            let s = &mut self.state;
            s.clumps.drop_clumps(&gone, &mut s.particles.clump);
        }
        self.rebuild(Some(&origin));
        removed
    }

    /// Adds a wall; returns its handle. Its interaction and, for an elastic wall, its
    /// material are checked as a particle material's are.
    pub fn add_wall(&mut self, wall: Wall) -> Result<WallId, DemError> {
        check_interaction(&wall.interaction)?;
        if let WallMaterial::Elastic(material) = &wall.material {
            check_material(material)?;
        }
        self.state
            .surface_loads
            .push(Self::fresh_surface_loads(&wall));
        self.state.walls.push(Some(wall));
        self.state.wall_interactions.push(Vec::new());
        self.state.needs_rebuild = true;
        self.unprepare();
        Ok(WallId(self.state.walls.len() as u32 - 1))
    }

    /// Sets how wall `wall` meets particles of `material`, in place of the wall's own
    /// interaction (a wall meets M1 and M2 spheres with different friction, say).
    pub fn set_wall_interaction(
        &mut self,
        wall: WallId,
        material: MaterialId,
        interaction: Interaction,
    ) -> Result<(), DemError> {
        check_interaction(&interaction)?;
        self.wall_mut(wall)?;
        check_material_id(material, self.state.materials.len())?;
        let row = &mut self.state.wall_interactions[wall.0 as usize];
        let m = material.0 as usize;
        if row.len() <= m {
            row.resize(m + 1, None);
        }
        row[m] = Some(interaction);
        self.unprepare();
        Ok(())
    }

    /// The interaction with which wall `wall` meets particles of `material`: the one set for
    /// that material, or else the wall's own; `None` for a wall or material that does not
    /// exist.
    pub fn wall_interaction(&self, wall: WallId, material: MaterialId) -> Option<Interaction> {
        let w = self.wall(wall)?;
        if material.0 as usize >= self.state.materials.len() {
            return None;
        }
        Some(self.wall_interaction_of(wall.0 as usize, w, material.0 as usize))
    }

    /// The interaction of wall index `w` (the wall `wall`) with material index `m`.
    fn wall_interaction_of(&self, w: usize, wall: &Wall, m: usize) -> Interaction {
        self.state.wall_interactions[w]
            .get(m)
            .copied()
            .flatten()
            .unwrap_or(wall.interaction)
    }

    /// Removes a wall (a hopper's gate, say).
    pub fn remove_wall(&mut self, id: WallId) -> Result<Wall, DemError> {
        let slot = self
            .state
            .walls
            .get_mut(id.0 as usize)
            .ok_or(DemError::UnknownWall(id.0))?;
        let wall = slot.take().ok_or(DemError::UnknownWall(id.0))?;
        self.state.wall_interactions[id.0 as usize].clear();
        self.state.needs_rebuild = true;
        Ok(wall)
    }

    /// Puts `wall` in the place of wall `id` (present or removed), under the same handle:
    /// what a container rebuilt around particles that stay needs (a hopper's new outlet).
    ///
    /// The contacts with the old wall forget their history: the next list build finds the
    /// new wall's candidates afresh, as for a wall just added. The new wall's per-material
    /// interactions, element loads and time-integrated load (`wall_impulse`) start from
    /// nothing. The other walls, the particles and every particle–particle history are left
    /// as they are, and so are the histories of contacts with the other walls, bit for bit.
    pub fn replace_wall(&mut self, id: WallId, wall: Wall) -> Result<(), DemError> {
        let k = id.0 as usize;
        if k >= self.state.walls.len() {
            return Err(DemError::UnknownWall(id.0));
        }
        check_interaction(&wall.interaction)?;
        if let WallMaterial::Elastic(material) = &wall.material {
            check_material(material)?;
        }
        self.state.surface_loads[k] = Self::fresh_surface_loads(&wall);
        self.state.walls[k] = Some(wall);
        self.state.wall_interactions[k].clear();
        if let Some(impulse) = self.state.wall_impulses.get_mut(k) {
            *impulse = Default::default();
        }
        self.state.wall_pairs = std::mem::take(&mut self.state.wall_pairs).without_wall(id.0);
        self.state.needs_rebuild = true;
        self.unprepare();
        Ok(())
    }

    /// How many wall handles have been given out, removed walls included: the handles are
    /// `WallId(0)` to `WallId(wall_slots() − 1)`.
    pub fn wall_slots(&self) -> usize {
        self.state.walls.len()
    }

    /// The wall `id`, if it is present.
    pub(super) fn wall_mut(&mut self, id: WallId) -> Result<&mut Wall, DemError> {
        self.state
            .walls
            .get_mut(id.0 as usize)
            .and_then(Option::as_mut)
            .ok_or(DemError::UnknownWall(id.0))
    }

    /// Moves a wall rigidly by `offset` [m].
    pub fn translate_wall(&mut self, id: WallId, offset: DVec3) -> Result<(), DemError> {
        self.wall_mut(id)?.translate(offset);
        self.state.wall_drift += offset.length();
        Ok(())
    }

    /// Sets the velocity a wall shows to the contact law [m/s] (it does not move it).
    pub fn set_wall_velocity(&mut self, id: WallId, velocity: DVec3) -> Result<(), DemError> {
        self.wall_mut(id)?.velocity = velocity;
        Ok(())
    }

    /// Sets the velocity and spin of particle `index` (test set-ups).
    pub fn set_particle_motion(&mut self, index: usize, velocity: DVec3, angular_velocity: DVec3) {
        self.state.particles.velocity[index] = velocity;
        self.state.particles.omega[index] = angular_velocity;
    }

    /// Sets the flags of particle `index` (`FLAG_*`). Whether it is a clump's member is the
    /// clump's to say: [`crate::FLAG_CLUMP_MEMBER`] is kept as its membership has it.
    pub fn set_particle_flags(&mut self, index: usize, flags: u8) {
        let p = &mut self.state.particles;
        let member = if p.clump[index] == crate::particles::NO_CLUMP {
            0
        } else {
            crate::particles::FLAG_CLUMP_MEMBER
        };
        p.flags[index] = flags & !crate::particles::FLAG_CLUMP_MEMBER | member;
        // The integrator's shared-body form holds only while no particle has flags.
        self.unprepare();
    }

    /// Mixes coefficients and checks Δt; runs before a step whenever the set-up changed.
    /// Marks the set-up changed: the next step prepares it again, with new load quanta.
    pub(super) fn unprepare(&mut self) {
        self.prepared = false;
        self.new_quanta = true;
    }

    pub(super) fn prepare(&mut self) -> Result<(), DemError> {
        let s = &self.state;
        let n = s.materials.len();
        self.pair_coeffs.clear();
        for a in 0..n {
            for b in 0..n {
                let c = match s.interactions[a * n + b] {
                    Some(i) => PairCoefficients::new(&s.materials[a], Some(&s.materials[b]), &i),
                    // Never read unless the two materials meet; checked below.
                    None => PairCoefficients::new(&s.materials[a], None, &Interaction::fan2023()),
                };
                self.pair_coeffs.push(c);
            }
        }
        let mut present = vec![false; n];
        for &m in &s.particles.material {
            present[m as usize] = true;
        }
        for a in 0..n {
            for b in 0..n {
                if present[a] && present[b] && s.interactions[a * n + b].is_none() {
                    return Err(DemError::MissingInteraction(a as u16, b as u16));
                }
            }
        }
        let mut wall_coeffs = std::mem::take(&mut self.wall_coeffs);
        wall_coeffs.clear();
        for (w, wall) in s.walls.iter().enumerate() {
            for (m, material) in s.materials.iter().enumerate() {
                wall_coeffs.push(match wall {
                    Some(wall) => PairCoefficients::with_wall(
                        material,
                        &wall.material,
                        &self.wall_interaction_of(w, wall, m),
                    ),
                    None => PairCoefficients::new(material, None, &Interaction::fan2023()),
                });
            }
        }
        self.wall_coeffs = wall_coeffs;
        self.bond_tables = BondTables::of(&self.pair_coeffs, &self.wall_coeffs);
        let mut coefficients = self.pair_coeffs.iter().chain(&self.wall_coeffs);
        self.pair_bonds = self.pair_coeffs.iter().any(|c| c.cohesion.bonds());
        self.wall_bonds = self.wall_coeffs.iter().any(|c| c.cohesion.bonds());
        self.bonds = self.pair_bonds || self.wall_bonds;
        self.area_cohesion =
            coefficients.any(|c| matches!(c.cohesion, crate::Cohesion::SimplifiedJkr { .. }));
        if let Some(t_r) = self.rayleigh_time() {
            let fraction = s.config.time_step / t_r;
            if fraction > s.config.max_rayleigh_fraction {
                return Err(DemError::TimeStepTooLarge {
                    time_step: s.config.time_step,
                    rayleigh_time: t_r,
                    fraction,
                    max_fraction: s.config.max_rayleigh_fraction,
                });
            }
        }
        self.uniform_body = uniform_body(&s.particles);
        self.uniform_free = uniform_free_body(&s.particles);
        if !s.clumps.is_empty() {
            // A restored state keeps no member indices; any edit may have moved them.
            self.state.clumps.find_members(&self.state.particles);
        }
        let s = &self.state;
        let p = &s.particles;
        let quanta = match s.load_quanta {
            Some(saved) if !self.new_quanta => saved,
            _ => {
                let g = s.config.gravity.length().max(1.0);
                let lightest = p.mass.iter().copied().fold(f64::INFINITY, f64::min);
                let reach = p
                    .position
                    .iter()
                    .zip(&p.radius)
                    .map(|(x, r)| x.length() + r)
                    .fold(0.0, f64::max);
                LoadQuanta::new(lightest * g, reach)
            }
        };
        self.state.load_quanta = Some(quanta);
        self.load_quanta = quanta;
        self.new_quanta = false;
        if self.bonds {
            let r_max = self
                .state
                .particles
                .radius
                .iter()
                .copied()
                .fold(0.0, f64::max);
            if self.cohesion_reach(r_max) > self.state.list_reach {
                // A cohesion that now reaches farther than the lists were built for.
                self.state.needs_rebuild = true;
            }
        }
        self.prepared = true;
        Ok(())
    }
}
