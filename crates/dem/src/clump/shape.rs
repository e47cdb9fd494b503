//! A clump as its user gives it (member spheres in any frame), and the rigid body it makes:
//! mass, centre of mass, principal moments and axes, and the members in the principal frame.

use glam::{DMat3, DQuat, DVec3};

use super::mass::{union_moments, Ball};
use super::principal::{principal_frame, rotation_quaternion};

/// Why a clump's members were refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClumpError {
    /// No member at all.
    #[error("a clump needs at least one member sphere; it has none")]
    Empty,
    /// A radius that is not a finite positive length.
    #[error("member {member}: radius {value} m must be finite and greater than 0")]
    Radius {
        /// Index of the member, from 0.
        member: usize,
        /// The radius given [m].
        value: f64,
    },
    /// A rod's aspect ratio that is not finite and at least 1.
    #[error("aspect ratio {value} must be finite and at least 1 (length over width)")]
    Aspect {
        /// The aspect ratio given [-].
        value: f64,
    },
    /// Too few beads to make a connected rod of the aspect ratio, or too many.
    #[error(
        "{value} beads cannot make a rod of aspect ratio {aspect}: it needs from {least} \
         (neighbours touching) to {MAX_ROD_BEADS} beads, and exactly 1 at aspect ratio 1"
    )]
    Beads {
        /// The number of beads given.
        value: usize,
        /// The aspect ratio [-].
        aspect: f64,
        /// The fewest beads that keep neighbours touching.
        least: usize,
    },
    /// A centre with a coordinate that is not finite.
    #[error("member {member}: centre {value:?} m must have finite coordinates")]
    Centre {
        /// Index of the member, from 0.
        member: usize,
        /// The centre given [m].
        value: [f64; 3],
    },
}

/// The most beads a generated rod may have.
pub const MAX_ROD_BEADS: usize = 64;

/// Member spheres (centres [m] and radii [m]) in the frame their user gave them in.
#[derive(Debug, Clone, PartialEq)]
pub struct ClumpShape {
    members: Vec<Ball>,
}

impl ClumpShape {
    /// The clump of `members`, refused when empty or when a member is not a finite ball.
    pub fn new(members: Vec<Ball>) -> Result<Self, ClumpError> {
        if members.is_empty() {
            return Err(ClumpError::Empty);
        }
        for (member, &(c, r)) in members.iter().enumerate() {
            if !(r > 0.0 && r.is_finite()) {
                return Err(ClumpError::Radius { member, value: r });
            }
            if !c.is_finite() {
                return Err(ClumpError::Centre {
                    member,
                    value: c.to_array(),
                });
            }
        }
        Ok(Self { members })
    }

    /// The members as given.
    pub fn members(&self) -> &[Ball] {
        &self.members
    }

    /// A rod of `beads` equal beads in a row along x, centred on the origin, its length (end
    /// to end) `aspect` times its width (a bead's diameter), of the volume of a sphere of
    /// diameter `diameter` [m], the equal-volume diameter. Neighbours overlap or touch: at
    /// least ⌈aspect⌉ beads (one at aspect 1, where the rod is that sphere).
    pub fn rod(aspect: f64, beads: usize, diameter: f64) -> Result<Self, ClumpError> {
        if !(aspect >= 1.0 && aspect.is_finite()) {
            return Err(ClumpError::Aspect { value: aspect });
        }
        if !(diameter > 0.0 && diameter.is_finite()) {
            return Err(ClumpError::Radius {
                member: 0,
                value: diameter / 2.0,
            });
        }
        // Centres (aspect − 1) w apart end to end, (aspect − 1) w / (beads − 1) between
        // neighbours, at most w.
        let least = if aspect == 1.0 {
            1
        } else {
            (aspect.ceil() as usize).max(2)
        };
        let fits = if aspect == 1.0 {
            beads == 1
        } else {
            (least..=MAX_ROD_BEADS).contains(&beads)
        };
        if !fits {
            return Err(ClumpError::Beads {
                value: beads,
                aspect,
                least,
            });
        }
        let row = |width: f64| -> Vec<Ball> {
            let span = (aspect - 1.0) * width;
            (0..beads)
                .map(|k| {
                    let t = if beads == 1 {
                        0.0
                    } else {
                        k as f64 / (beads - 1) as f64 - 0.5
                    };
                    (DVec3::new(t * span, 0.0, 0.0), width / 2.0)
                })
                .collect()
        };
        // The union's volume scales as the width cubed: the width of unit volume ratio, then
        // the one of the sphere's volume.
        let unit = union_moments(&row(1.0)).volume;
        let sphere = std::f64::consts::PI / 6.0 * diameter.powi(3);
        Self::new(row((sphere / unit).cbrt()))
    }

    /// The rigid body of these members at `density` [kg/m³].
    pub fn body(&self, density: f64) -> ClumpBody {
        // Moments about the members' mean centre: about a far origin, the second moment's
        // V c cᵀ would swamp the part that the inertia is made of.
        let origin =
            self.members.iter().map(|&(c, _)| c).sum::<DVec3>() / self.members.len() as f64;
        let near: Vec<Ball> = self.members.iter().map(|&(c, r)| (c - origin, r)).collect();
        let m = union_moments(&near);
        let offset = m.first / m.volume;
        let centre = origin + offset;
        // ∫ x xᵀ about the centre, then the inertia tensor tr(S) 1 − S, per unit density.
        let outer = DMat3::from_cols(offset * offset.x, offset * offset.y, offset * offset.z);
        let s = m.second - outer * m.volume;
        let trace = s.x_axis.x + s.y_axis.y + s.z_axis.z;
        let inertia = DMat3::from_diagonal(DVec3::splat(trace)) - s;
        let (moments, frame) = principal_frame(inertia);
        let axes = rotation_quaternion(frame);
        let members = self
            .members
            .iter()
            .map(|&(c, r)| (axes.inverse() * (c - centre), r))
            .collect();
        ClumpBody {
            volume: m.volume,
            mass: density * m.volume,
            centre,
            principal_inertia: moments * density,
            axes,
            members,
        }
    }
}

/// A clump as a rigid body.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClumpBody {
    /// Volume of the members' union [m³].
    pub volume: f64,
    /// Mass [kg].
    pub mass: f64,
    /// Centre of mass [m], in the frame the members were given in.
    pub centre: DVec3,
    /// Principal moments of inertia about the centre of mass [kg m²], ascending.
    pub principal_inertia: DVec3,
    /// The principal frame: the rotation from it to the frame the members were given in.
    pub axes: DQuat,
    /// The members' centres [m] in the principal frame, about the centre of mass, and their
    /// radii [m].
    pub members: Vec<Ball>,
}

impl ClumpBody {
    /// The body of the members scaled by `factor` about the frame's origin (a grain of the
    /// same shape, `factor` times as long): volume and mass × factor³, centre and members ×
    /// factor, principal moments × factor⁵, the same axes. A factor of 1 gives these bits.
    pub fn scaled(&self, factor: f64) -> ClumpBody {
        let cube = factor * factor * factor;
        ClumpBody {
            volume: self.volume * cube,
            mass: self.mass * cube,
            centre: self.centre * factor,
            principal_inertia: self.principal_inertia * (cube * factor * factor),
            axes: self.axes,
            members: self
                .members
                .iter()
                .map(|&(c, r)| (c * factor, r * factor))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn a_scaled_body_is_the_body_of_the_scaled_members() {
        // Three members, two overlapping: the union's moments are homogeneous in length, so
        // scaling the body and making the body of scaled members agree to the union's
        // rounding (the triple-overlap integral is absent here, so closed forms on both sides).
        let members = vec![
            (DVec3::new(0.0, 0.0, 0.0), 1.0),
            (DVec3::new(1.2, 0.3, 0.0), 0.8),
            (DVec3::new(-0.5, 1.6, 0.4), 0.6),
        ];
        let k = 2.5e-3;
        let scaled = ClumpShape::new(members.clone())
            .unwrap()
            .body(2500.0)
            .scaled(k);
        let direct = ClumpShape::new(members.iter().map(|&(c, r)| (c * k, r * k)).collect())
            .unwrap()
            .body(2500.0);
        assert!((scaled.mass / direct.mass - 1.0).abs() < 1e-13);
        assert!((scaled.centre - direct.centre).length() < 1e-15);
        for a in 0..3 {
            let (x, y) = (scaled.principal_inertia[a], direct.principal_inertia[a]);
            assert!((x / y - 1.0).abs() < 1e-12, "axis {a}: {x} against {y}");
        }
        let one = ClumpShape::new(members).unwrap().body(2500.0);
        assert_eq!(one.scaled(1.0), one, "a factor of 1 keeps the bits");
    }

    #[test]
    fn bad_members_are_refused_with_the_member_and_the_value() {
        assert_eq!(ClumpShape::new(vec![]), Err(ClumpError::Empty));
        let e = ClumpShape::new(vec![(DVec3::ZERO, 0.001), (DVec3::X, 0.0)]).unwrap_err();
        assert_eq!(
            e,
            ClumpError::Radius {
                member: 1,
                value: 0.0
            }
        );
        assert!(e.to_string().contains("member 1") && e.to_string().contains("greater than 0"));
        let nan = ClumpShape::new(vec![(DVec3::ZERO, f64::NAN)]).unwrap_err();
        assert!(matches!(nan, ClumpError::Radius { member: 0, .. }));
        let inf = ClumpShape::new(vec![(DVec3::new(0.0, f64::INFINITY, 0.0), 1.0)]).unwrap_err();
        assert!(matches!(inf, ClumpError::Centre { member: 0, .. }));
    }

    #[test]
    fn rods_have_the_equal_volume_sphere_s_volume_and_their_aspect_ratio() {
        // Aspect ratios 1 to 3 with the fewest and with more beads: the union's volume is the
        // sphere's of the given diameter (to the union's stated 1e-5, exactly where no three
        // beads overlap), and the length end to end over the width is the aspect ratio.
        let d: f64 = 0.004;
        let sphere = PI / 6.0 * d.powi(3);
        for (aspect, beads) in [(1.0, 1), (1.5, 2), (2.0, 2), (2.0, 5), (3.0, 3), (3.0, 9)] {
            let rod = ClumpShape::rod(aspect, beads, d).expect("a rod");
            let body = rod.body(1.0);
            assert!(
                (body.volume - sphere).abs() <= 1e-5 * sphere,
                "{aspect} {beads}"
            );
            let m = rod.members();
            let width = 2.0 * m[0].1;
            let length = m[m.len() - 1].0.x - m[0].0.x + width;
            assert!((length / width - aspect).abs() <= 1e-12, "{aspect} {beads}");
        }
        // Refusals: aspect below 1, too few beads to touch, more than one at aspect 1.
        assert_eq!(
            ClumpShape::rod(0.5, 2, d),
            Err(ClumpError::Aspect { value: 0.5 })
        );
        let gap = ClumpShape::rod(3.0, 2, d).unwrap_err();
        assert_eq!(
            gap,
            ClumpError::Beads {
                value: 2,
                aspect: 3.0,
                least: 3
            }
        );
        assert!(gap.to_string().contains("from 3"), "{gap}");
        assert!(ClumpShape::rod(1.0, 2, d).is_err());
        assert!(ClumpShape::rod(2.0, MAX_ROD_BEADS + 1, d).is_err());
    }

    #[test]
    fn a_dumbbell_of_touching_balls_has_the_textbook_mass_properties() {
        // Two balls of radius r touching at the origin along an arbitrary axis: mass 2 m,
        // centre at the contact, I about the axis 2 (2/5 m r²), across it 2 (2/5 m r² + m r²)
        // (parallel axes), the long axis being the principal axis of the largest moment's
        // complement: the smallest moment.
        let (r, rho) = (0.002, 2500.0);
        let axis = DVec3::new(1.0, 1.0, -0.5).normalize();
        let shape = ClumpShape::new(vec![(axis * r, r), (-axis * r, r)]).expect("valid");
        let body = shape.body(rho);
        let m = rho * 4.0 / 3.0 * PI * r.powi(3);
        assert!((body.mass - 2.0 * m).abs() <= 1e-13 * m);
        assert!(body.centre.length() <= 1e-15);
        let along = 2.0 * 0.4 * m * r * r;
        let across = 2.0 * (0.4 * m * r * r + m * r * r);
        let want = DVec3::new(along, across, across);
        assert!((body.principal_inertia - want).abs().max_element() <= 1e-12 * across);
        // The first principal axis is the dumbbell's.
        let long = body.axes * DVec3::X;
        assert!(long.dot(axis).abs() >= 1.0 - 1e-12, "{long}");
        // The members, in the principal frame, lie on its x axis at ±r.
        for &(c, _) in &body.members {
            assert!(
                (c.x.abs() - r).abs() <= 1e-15 && c.y.abs() + c.z.abs() <= 1e-15,
                "{c}"
            );
        }
    }
}
