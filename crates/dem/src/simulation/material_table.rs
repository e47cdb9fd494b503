//! Installing a [`MaterialTable`]: its particle materials with every pair interaction among
//! them, and walls made of its materials with their interaction with each particle material
//! (docs/physics.md §1.2). Everything is resolved before the simulation changes, so a refused
//! table leaves nothing behind.

use super::*;
use crate::material::{MaterialTable, MaterialTableError};

/// The ids under which a material table's particle materials were registered, by name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MaterialIds {
    entries: Vec<(String, MaterialId)>,
}

impl MaterialIds {
    /// The id of particle material `name`, if it was registered.
    pub fn get(&self, name: &str) -> Option<MaterialId> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|&(_, id)| id)
    }

    /// The names and ids, in the order they were registered.
    pub fn iter(&self) -> impl Iterator<Item = (&str, MaterialId)> {
        self.entries.iter().map(|(n, id)| (n.as_str(), *id))
    }
}

impl Simulation {
    /// Registers the materials of `table` named in `particle_materials` as particle
    /// materials, in that order, each with its self-interaction, and sets the interaction of
    /// every two of them (listed, or mixed from their self-pairs). Materials registered
    /// earlier get no interaction with them ([`Simulation::set_interaction`] gives one).
    pub fn add_material_table(
        &mut self,
        table: &MaterialTable,
        particle_materials: &[&str],
    ) -> Result<MaterialIds, DemError> {
        table.check()?;
        let mut materials = Vec::with_capacity(particle_materials.len());
        for (i, &name) in particle_materials.iter().enumerate() {
            let key = format!("particle_materials[{i}]");
            table.known(&key, name)?;
            if let Some(first) = particle_materials[..i].iter().position(|&n| n == name) {
                return Err(MaterialTableError::RepeatedName {
                    key,
                    name: name.to_owned(),
                    first: format!("particle_materials[{first}]"),
                }
                .into());
            }
            let material = table.material(name)?;
            // The table's ranges are the engine's, but E derived from a huge G can overflow.
            edit::check_material(&material)?;
            materials.push(material);
        }
        let n = particle_materials.len();
        let mut interactions = Vec::with_capacity(n * n);
        for a in particle_materials {
            for b in particle_materials {
                interactions.push(table.interaction(a, b)?);
            }
        }
        let first = self.state.materials.len();
        let mut entries = Vec::with_capacity(n);
        for (i, (&name, material)) in particle_materials.iter().zip(materials).enumerate() {
            let id = self.add_material(material, interactions[i * n + i])?;
            entries.push((name.to_owned(), id));
        }
        for a in 0..n {
            for b in a + 1..n {
                let id = |k: usize| MaterialId((first + k) as u16);
                self.set_interaction(id(a), id(b), interactions[a * n + b])?;
            }
        }
        Ok(MaterialIds { entries })
    }

    /// Makes wall `wall` of the table's material `material`: an elastic wall of it, meeting
    /// each particle material of `ids` with that pair's interaction from the table.
    pub fn set_wall_from_table(
        &mut self,
        wall: WallId,
        table: &MaterialTable,
        ids: &MaterialIds,
        material: &str,
    ) -> Result<(), DemError> {
        self.wall_mut(wall)?;
        table.known("wall material", material)?;
        let wall_material = table.wall_material(material)?;
        let interactions = ids
            .iter()
            .map(|(name, id)| Ok((id, table.interaction(name, material)?)))
            .collect::<Result<Vec<_>, MaterialTableError>>()?;
        self.wall_mut(wall)?.material = wall_material;
        for (id, interaction) in interactions {
            self.set_wall_interaction(wall, id, interaction)?;
        }
        self.unprepare();
        Ok(())
    }
}
