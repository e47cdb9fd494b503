//! The batched contact kernel: the force machinery that evaluates the paper's contact laws
//! (Hertz + restitution dashpot, Mindlin no-slip, Eq. 8 constant rolling torque, no clamp)
//! for a batch of contacts (touching, or bonded across a gap) stored as structure of
//! arrays. It holds no law of its own.
//!
//! The scalar pipeline in `ContactLaws::resolve` is one long chain of dependent square roots
//! and divisions per contact, too long for the processor to overlap consecutive contacts.
//! Here every stage is a loop over the contacts without branches, so the compiler evaluates
//! two contacts per SSE2 instruction (`sqrtpd`, `divpd`) and independent contacts overlap.
//! Each stage calls the law's own function from `contact`: `normal::hertz`,
//! `damping::dashpot`, `rolling::constant_torque_scale`, `tangential::mindlin_stiffness`,
//! `coulomb_limit` and `no_slip_dashpot` as they are, and the lane forms
//! `tangential::rotate_and_slip_lane`, `tangential::no_slip_force_lane` and
//! `rolling::constant_torque_levers_lane` where the scalar form branches or works on
//! vectors; the contact module's tests hold the lane forms to the scalar ones bit for bit,
//! and a test here holds the whole kernel to `ContactLaws::resolve`.

use glam::DVec3;

use super::bond_rows::BondRows;
use crate::contact::cohesion::{
    bonded_stage_lane, LAWS_MIXED, LAW_BRIDGE, LAW_DRY, LAW_JKR, OUTCOME_BRIDGE_ONLY,
    OUTCOME_CONTACT,
};
use crate::contact::geometry::{effective_radius, lever_arm};
use crate::contact::tangential;
use crate::contact::{damping, normal, rolling};
use crate::material::{harmonic, PairCoefficients};

/// Contacts per batch: the arrays (≈ 40 × 8 × BATCH bytes) stay in the L1 cache.
pub const BATCH: usize = 32;

/// Contacts per vector of the widest build the kernel is written for (eight f64 in 512
/// bits; a multiple of the narrower builds' four and two). BATCH is a multiple of it.
const VECTOR: usize = 8;
const _: () = assert!(BATCH.is_multiple_of(VECTOR));

/// One batch of contacts (touching, or bonded across a gap): inputs gathered by the caller,
/// outputs filled by [`Batch::resolve`]. All vectors are components x, y, z. Pair "i–j" follows `ContactGeometry`: n points from j to i.
///
/// Laid out in declaration order from a 64-byte boundary, the count last, so that every
/// lane array starts on a cache line: vector loads of a lane array then never straddle two
/// lines, wherever the allocator puts the batch.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub struct Batch {
    /// Centre offset x_i − x_j [m].
    pub d: [[f64; BATCH]; 3],
    /// Squared centre distance [m²] (pairs only).
    pub dist2: [f64; BATCH],
    /// Overlap δ_n [m] (walls only: there `d` holds the unit normal, wall to particle).
    pub overlap: [f64; BATCH],
    /// Radii R_i, R_j [m].
    pub radius: [[f64; BATCH]; 2],
    /// Masses m_i, m_j [kg] (m_j unused for walls).
    pub mass: [[f64; BATCH]; 2],
    /// Velocity difference v_i − v_j [m/s].
    pub dv: [[f64; BATCH]; 3],
    /// Angular velocities ω_i and ω_j [rad/s].
    pub omega: [[[f64; BATCH]; 3]; 2],
    /// Tangential history ξ before (input) and after (output) the step [m].
    pub xi: [[f64; BATCH]; 3],
    /// Pair coefficients of each contact ([`PairCoefficients`], one array per field).
    pub coeff: CoefficientRows,
    /// Output: force on i [N].
    pub force: [[f64; BATCH]; 3],
    /// Output: torque on i [N m].
    pub torque_i: [[f64; BATCH]; 3],
    /// Output: torque on j [N m].
    pub torque_j: [[f64; BATCH]; 3],
    /// Output: overlap over the smaller radius [-].
    pub overlap_fraction: [f64; BATCH],
    /// Intermediate values of the kernel's passes.
    stages: Stages,
    /// Bonding laws of the contacts, and what they made of each (read and written only by
    /// the bonded resolves).
    pub bond: BondRows,
    /// Contacts filled in [-].
    pub len: usize,
}

impl Default for Batch {
    fn default() -> Self {
        let z = [0.0; BATCH];
        Self {
            len: 0,
            d: [z; 3],
            dist2: z,
            overlap: z,
            radius: [z; 2],
            mass: [z; 2],
            dv: [z; 3],
            omega: [[z; 3]; 2],
            xi: [z; 3],
            coeff: CoefficientRows::default(),
            force: [z; 3],
            torque_i: [z; 3],
            torque_j: [z; 3],
            overlap_fraction: z,
            stages: Stages::default(),
            bond: BondRows::default(),
        }
    }
}

impl Batch {
    /// Fills slot `m` with one pair's motion: centre offset `d` = x_i − x_j [m] and its
    /// square, velocity difference `dv` = v_i − v_j [m/s], spins `omega_i`, `omega_j`
    /// [rad/s] and tangential history `xi` [m]. Inlined: the force loop's gather calls it
    /// once per touching pair.
    #[inline(always)]
    pub fn set_pair_motion(
        &mut self,
        m: usize,
        (d, dv): (DVec3, DVec3),
        (omega_i, omega_j): (DVec3, DVec3),
        xi: DVec3,
    ) {
        let (wi, wj) = (omega_i, omega_j);
        // Components named, not indexed, so that no bounds check survives in the gather.
        for (a, (x, v, u, w, z)) in [
            (d.x, dv.x, wi.x, wj.x, xi.x),
            (d.y, dv.y, wi.y, wj.y, xi.y),
            (d.z, dv.z, wi.z, wj.z, xi.z),
        ]
        .into_iter()
        .enumerate()
        {
            self.d[a][m] = x;
            self.dv[a][m] = v;
            self.omega[0][a][m] = u;
            self.omega[1][a][m] = w;
            self.xi[a][m] = z;
        }
        self.dist2[m] = d.length_squared();
    }

    /// Sets the pair coefficients of every slot, for a batch whose contacts all share them
    /// (one material): the gather then skips the six per-contact copies. Inlined: the wall
    /// pass calls it once per wall, and on the paper's case a call costs as much as the fill.
    #[inline(always)]
    pub fn fill_coefficients(&mut self, c: &PairCoefficients) {
        self.coeff.fill(c);
    }

    /// Evaluates every particle–particle contact of the batch for time step `dt` [s],
    /// updating `xi`.
    #[inline(never)]
    pub fn resolve_pairs(&mut self, dt: f64) {
        self.resolve::<false, false, LAW_DRY>(dt, SharedBody::default());
    }

    /// As [`Batch::resolve_pairs`], for a batch whose spheres all have radius `radius` [m] and
    /// mass `mass` [kg] (the `radius` and `mass` arrays must hold them). R* and m* are then
    /// constants, which spares three of the eleven divisions and square roots per contact.
    /// Bit-identical to `resolve_pairs` in forces, torques and history (R* and m* are the
    /// same expressions); the overlap fraction is formed with a reciprocal and may differ in
    /// its last bit.
    #[inline(never)]
    pub fn resolve_pairs_uniform(&mut self, dt: f64, radius: f64, mass: f64) {
        self.resolve::<false, true, LAW_DRY>(dt, SharedBody::of(radius, mass));
    }

    /// Evaluates every particle–wall contact of the batch for time step `dt` [s], updating
    /// `xi`. A wall is a body of infinite radius and mass at rest in rotation (docs/physics.md §5):
    /// R* = R_i, m* = m_i, lever a_j = 0, ω_j = 0 (the caller stores zero there).
    #[inline(never)]
    pub fn resolve_walls(&mut self, dt: f64) {
        self.resolve::<true, false, LAW_DRY>(dt, SharedBody::default());
    }

    /// As [`Batch::resolve_pairs`], for pairs whose material pairs may bond (JKR, liquid
    /// bridges; `bond` holds each slot's law): the slots may be bonded pairs apart
    /// (overlap ≤ 0). Each slot's outcome is left in `bond.outcome`; a slot whose bond broke
    /// gets no force and no history, one held by a bridge alone the bridge's pull and no
    /// history.
    #[inline(never)]
    pub fn resolve_bonded_pairs(&mut self, dt: f64) {
        self.resolve_bonded::<false, false>(dt, SharedBody::default());
    }

    /// The bonded resolve for the batch's laws: the loop of one law where every slot has it.
    #[inline(always)]
    fn resolve_bonded<const WALL: bool, const UNIFORM: bool>(
        &mut self,
        dt: f64,
        shared: SharedBody,
    ) {
        match self.bond.laws(self.len) {
            LAW_JKR => self.resolve::<WALL, UNIFORM, LAW_JKR>(dt, shared),
            LAW_BRIDGE => self.resolve::<WALL, UNIFORM, LAW_BRIDGE>(dt, shared),
            _ => self.resolve::<WALL, UNIFORM, LAWS_MIXED>(dt, shared),
        }
    }

    /// As [`Batch::resolve_walls`], for particle–wall pairs that may bond, as
    /// [`Batch::resolve_bonded_pairs`] does for pairs: `d` holds the unit normal and
    /// `overlap` the overlap, negative across a gap.
    #[inline(never)]
    pub fn resolve_bonded_walls(&mut self, dt: f64) {
        self.resolve_bonded::<true, false>(dt, SharedBody::default());
    }

    /// [`Batch::resolve_bonded_pairs`] for equal spheres ([`Batch::resolve_pairs_uniform`]).
    #[inline(never)]
    pub fn resolve_bonded_pairs_uniform(&mut self, dt: f64, radius: f64, mass: f64) {
        self.resolve_bonded::<false, true>(dt, SharedBody::of(radius, mass));
    }

    /// The laws over the batch in four passes, each a loop over the contacts.
    ///
    /// One pass per contact would chain, within each contact, up to six dependent square
    /// roots and divisions (|d| → 1/|d| → n → |ξ|/|proj| → the Coulomb cap), about 90 cycles
    /// of latency, in a loop body too long for the processor to start the next contacts'
    /// divisions meanwhile: it waited on the divider. Cut into passes, each loop carries at
    /// most two dependent ones and its iterations are independent, so the divider works on
    /// several contacts at once. Every contact still gets the same operations in the same
    /// order; the intermediate values wait in [`Stages`] (L1-resident).
    #[inline(always)]
    fn resolve<const WALL: bool, const UNIFORM: bool, const LAWS: u8>(
        &mut self,
        dt: f64,
        shared: SharedBody,
    ) {
        // The contacts rounded up to whole vectors of the widest build. The slots past
        // `len` hold what an earlier batch left there (finite numbers from real contacts,
        // or a new batch's zeros) and are resolved too, their results never read. Otherwise
        // the compiler's scalar remainder loop would resolve a batch's last few contacts
        // one at a time, each chaining its square roots and divisions: about 25 ns a
        // contact against 7 (`cargo bench --manifest-path bench/engine/Cargo.toml --bench contact_kernel`,
        // `batch_resolve_walls_short_batch`). Every pair run, wall run and step ends with
        // such a batch.
        let n = self.len.next_multiple_of(VECTOR).min(BATCH);
        let st = &mut self.stages;

        // Pass 1, geometry.
        for k in 0..n {
            let (ri, rj) = (self.radius[0][k], self.radius[1][k]);
            let (mi, mj) = (self.mass[0][k], self.mass[1][k]);
            if WALL {
                // The wall loop found the closest point: n and δ come in directly (the
                // later passes read n from `d`, not from a copy).
                let overlap = self.overlap[k];
                self.overlap_fraction[k] = overlap / ri;
                st.overlap[k] = overlap;
                (st.arm[0][k], st.arm[1][k]) = (lever_arm(ri, overlap), 0.0);
            } else {
                // `geometry::sphere_sphere`: n = d/|d|, δ = R_i + R_j − |d|, R* and m*
                // harmonic.
                let sum = ri + rj;
                let dist = self.dist2[k].sqrt();
                let overlap = sum - dist;
                let inv = 1.0 / dist;
                for c in 0..3 {
                    st.normal[c][k] = self.d[c][k] * inv;
                }
                if UNIFORM {
                    self.overlap_fraction[k] = overlap * shared.inv_radius;
                } else {
                    self.overlap_fraction[k] = overlap / ri.min(rj);
                    st.r_eff[k] = effective_radius(ri, rj, sum);
                    st.m_eff[k] = harmonic(mi, mj);
                }
                st.overlap[k] = overlap;
                (st.arm[0][k], st.arm[1][k]) = (lever_arm(ri, overlap), lever_arm(rj, overlap));
            }
        }

        // Pass 1b, bonds only: the normal stage of each slot's bonding law
        // (`bonded_stage_lane`), in a loop of its own so that it vectorises. Over every
        // slot: with a trip count the compiler does not know, it keeps a bridge's loop
        // scalar (it weighs the vector loop's set-up against a count that may be small).
        if LAWS != LAW_DRY {
            for k in 0..BATCH {
                let rows = (&self.radius, &self.coeff.e_star, &mut self.bond);
                bonded_stage::<WALL, UNIFORM, LAWS>(rows, st, k, shared);
            }
        }

        // Pass 2, normal force (§2.1: `normal::hertz`, `damping::dashpot`), contact-point
        // velocity, and the rolling torque's scale (Eq. 8).
        for k in 0..n {
            // A wall is a body of infinite radius and mass: R* = R_i, m* = m_i (§5).
            let (r_eff, m_eff) = if WALL {
                (self.radius[0][k], self.mass[0][k])
            } else if UNIFORM {
                (shared.r_eff, shared.m_eff)
            } else {
                (st.r_eff[k], st.m_eff[k])
            };
            let (e_star, rolling_friction, prefactor) = (
                self.coeff.e_star[k],
                self.coeff.rolling_friction[k],
                self.coeff.damping[k],
            );
            let nrm = normal_of::<WALL>(&self.d, &st.normal, k);
            let overlap = st.overlap[k];
            let (arm_i, arm_j) = (st.arm[0][k], st.arm[1][k]);

            // Contact-point relative velocity (§1): v = Δv − (a_i ω_i + a_j ω_j) × n.
            let w = [
                arm_i * self.omega[0][0][k] + arm_j * self.omega[1][0][k],
                arm_i * self.omega[0][1][k] + arm_j * self.omega[1][1][k],
                arm_i * self.omega[0][2][k] + arm_j * self.omega[1][2][k],
            ];
            let wxn = cross(w, nrm);
            let v = [
                self.dv[0][k] - wxn[0],
                self.dv[1][k] - wxn[1],
                self.dv[2][k] - wxn[2],
            ];
            let v_n = dot(v, nrm);
            for c in 0..3 {
                st.v_t[c][k] = v[c] - v_n * nrm[c];
            }

            // The elastic force, its stiffness and contact radius, and the load of friction
            // and rolling: Hertz's, or the pair's bonding law's (pass 1b).
            let (f_ne, stiffness, contact_radius, load) = if LAWS != LAW_DRY {
                (st.f_ne[k], st.stiffness[k], st.a[k], st.load[k])
            } else {
                let hertz = normal::hertz(e_star, r_eff, overlap);
                (
                    hertz.force,
                    hertz.stiffness,
                    hertz.contact_radius,
                    hertz.force,
                )
            };
            let gamma_n = damping::dashpot(prefactor, stiffness, m_eff);
            st.a[k] = contact_radius;
            st.f_ne[k] = f_ne;
            st.gamma_n[k] = gamma_n;
            st.f_n[k] = if LAWS != LAW_DRY {
                // The attraction after the dashpot, as `ContactLaws::resolve` subtracts it.
                f_ne - gamma_n * v_n - st.pull[k]
            } else {
                f_ne - gamma_n * v_n
            };

            // s = μ_r F_ne/|ω_rel| (Eq. 8), zero without relative spin or rolling friction.
            let omega_rel = [
                self.omega[0][0][k] - self.omega[1][0][k],
                self.omega[0][1][k] - self.omega[1][1][k],
                self.omega[0][2][k] - self.omega[1][2][k],
            ];
            let w2 = dot(omega_rel, omega_rel);
            st.rolling[k] = rolling::constant_torque_scale(rolling_friction, load, w2);
        }

        // Pass 3, history into the tangent plane keeping its length (a zero or normal history
        // becomes zero), plus the step's slip v_t Δt.
        for k in 0..n {
            let nrm = normal_of::<WALL>(&self.d, &st.normal, k);
            let xi = [self.xi[0][k], self.xi[1][k], self.xi[2][k]];
            let v_t = [st.v_t[0][k], st.v_t[1][k], st.v_t[2][k]];
            let xi = tangential::rotate_and_slip_lane(xi, nrm, v_t, dt);
            for (c, x) in xi.into_iter().enumerate() {
                self.xi[c][k] = x;
            }
        }

        // Pass 4, Mindlin no-slip: spring on ξ, Coulomb cap μ F_ne, dashpot
        // γ_t = γ_n √(4G*/E*) only while sticking; then the torques.
        for k in 0..n {
            let (g_star, friction, ratio) = (
                self.coeff.g_star[k],
                self.coeff.friction[k],
                self.coeff.stiffness_ratio_sqrt[k],
            );
            let nrm = normal_of::<WALL>(&self.d, &st.normal, k);
            let v_t = [st.v_t[0][k], st.v_t[1][k], st.v_t[2][k]];
            let s_t = tangential::mindlin_stiffness(g_star, st.a[k]);
            let gamma_t = tangential::no_slip_dashpot(st.gamma_n[k], ratio);
            let load = if LAWS != LAW_DRY {
                st.load[k]
            } else {
                st.f_ne[k]
            };
            let cap = tangential::coulomb_limit(friction, load);
            let mut xi = [self.xi[0][k], self.xi[1][k], self.xi[2][k]];
            let f_t = tangential::no_slip_force_lane(&mut xi, v_t, s_t, cap, gamma_t);

            // Torques (`rolling::constant_torque_levers`). ω_rel is formed again here (three
            // subtractions of inputs, the same bits as in pass 2) rather than stored and
            // reloaded.
            let omega_rel = [
                self.omega[0][0][k] - self.omega[1][0][k],
                self.omega[0][1][k] - self.omega[1][1][k],
                self.omega[0][2][k] - self.omega[1][2][k],
            ];
            let (s, f_n) = (st.rolling[k], st.f_n[k]);
            let arms = (st.arm[0][k], st.arm[1][k]);
            let nxf = cross(nrm, f_t);
            let (torque_i, torque_j) =
                rolling::constant_torque_levers_lane(nxf, s, omega_rel, arms);
            for c in 0..3 {
                self.xi[c][k] = xi[c];
                self.force[c][k] = f_n * nrm[c] + f_t[c];
                self.torque_i[c][k] = torque_i[c];
                self.torque_j[c][k] = torque_j[c];
            }
        }

        // Pass 5, bonds only: a slot held by a bridge alone gets the bridge's pull along n,
        // one whose bond broke nothing; neither keeps a history (`ContactLaws::resolve`).
        if LAWS != LAW_DRY {
            for k in 0..n {
                let outcome = self.bond.outcome[k];
                let (contact, bridge) =
                    (outcome == OUTCOME_CONTACT, outcome == OUTCOME_BRIDGE_ONLY);
                let nrm = normal_of::<WALL>(&self.d, &st.normal, k);
                let pull = st.pull[k];
                for (c, n_c) in nrm.into_iter().enumerate() {
                    let alone = if bridge { -pull * n_c } else { 0.0 };
                    self.force[c][k] = if contact { self.force[c][k] } else { alone };
                    self.torque_i[c][k] = if contact { self.torque_i[c][k] } else { 0.0 };
                    self.torque_j[c][k] = if contact { self.torque_j[c][k] } else { 0.0 };
                    self.xi[c][k] = if contact { self.xi[c][k] } else { 0.0 };
                }
            }
        }
    }
}

/// The normal stage of slot `k`'s bonding law into the stages (pass 1b of
/// [`Batch::resolve`]), from the batch's radii, E* and bonding rows.
#[inline(always)]
fn bonded_stage<const WALL: bool, const UNIFORM: bool, const LAWS: u8>(
    (radius, e_star, bond): (&[[f64; BATCH]; 2], &[f64; BATCH], &mut BondRows),
    st: &mut Stages,
    k: usize,
    shared: SharedBody,
) {
    let r_eff = if WALL {
        radius[0][k]
    } else if UNIFORM {
        shared.r_eff
    } else {
        st.r_eff[k]
    };
    let e_star = e_star[k];
    let constants = bond.constants(k, e_star);
    let lane = bonded_stage_lane::<LAWS>(&constants, e_star, r_eff, st.overlap[k]);
    bond.outcome[k] = lane.outcome;
    st.f_ne[k] = lane.elastic;
    st.stiffness[k] = lane.stiffness;
    st.a[k] = lane.contact_radius;
    st.load[k] = lane.load;
    st.pull[k] = lane.pull;
}

/// The unit normal of contact `k`: a wall's comes in `d`, a pair's is formed in pass 1.
#[inline(always)]
fn normal_of<const WALL: bool>(
    d: &[[f64; BATCH]; 3],
    formed: &[[f64; BATCH]; 3],
    k: usize,
) -> [f64; 3] {
    let n = if WALL { d } else { formed };
    [n[0][k], n[1][k], n[2][k]]
}

/// What the passes of [`Batch::resolve`] hand on to the next, per contact.
#[derive(Clone, Debug)]
struct Stages {
    /// Unit normal n of a pair, from j to i [-] (a wall's stays in `Batch::d`).
    normal: [[f64; BATCH]; 3],
    /// Overlap δ_n [m].
    overlap: [f64; BATCH],
    /// Effective radius R* [m] of unequal spheres (walls and equal spheres need none).
    r_eff: [f64; BATCH],
    /// Effective mass m* [kg] of unequal spheres.
    m_eff: [f64; BATCH],
    /// Lever arms a_i, a_j [m].
    arm: [[f64; BATCH]; 2],
    /// Tangential contact-point velocity v_t [m/s].
    v_t: [[f64; BATCH]; 3],
    /// Contact radius √(R* δ) [m].
    a: [f64; BATCH],
    /// Elastic normal force F_ne [N].
    f_ne: [f64; BATCH],
    /// Normal damping coefficient γ_n [kg/s].
    gamma_n: [f64; BATCH],
    /// Normal force F_n = F_ne − γ_n v_n [N].
    f_n: [f64; BATCH],
    /// Rolling torque scale s = μ_r F_ne/|ω_rel| [N m s].
    rolling: [f64; BATCH],
    /// Normal load of friction and rolling [N] (bonded resolves only; F_ne otherwise).
    load: [f64; BATCH],
    /// Normal stiffness of the dashpot [N/m] (bonded resolves only).
    stiffness: [f64; BATCH],
    /// Cohesive attraction [N] (bonded resolves only).
    pull: [f64; BATCH],
}

impl Default for Stages {
    fn default() -> Self {
        let z = [0.0; BATCH];
        Self {
            normal: [z; 3],
            overlap: z,
            r_eff: z,
            m_eff: z,
            arm: [z; 2],
            v_t: [z; 3],
            a: z,
            f_ne: z,
            gamma_n: z,
            f_n: z,
            rolling: z,
            load: z,
            stiffness: z,
            pull: z,
        }
    }
}

/// The pair coefficients of a batch's contacts: the fields of [`PairCoefficients`] the laws
/// read, one array over the slots per field.
#[derive(Clone, Debug)]
pub struct CoefficientRows {
    /// Effective Young's modulus E* [Pa].
    pub e_star: [f64; BATCH],
    /// Effective shear modulus G* [Pa].
    pub g_star: [f64; BATCH],
    /// Sliding friction μ_s [-].
    pub friction: [f64; BATCH],
    /// Rolling friction μ_r [-].
    pub rolling_friction: [f64; BATCH],
    /// Dashpot prefactor 2√(5/6)|β(e)| [-].
    pub damping: [f64; BATCH],
    /// √(4G*/E*) [-].
    pub stiffness_ratio_sqrt: [f64; BATCH],
}

impl Default for CoefficientRows {
    fn default() -> Self {
        let z = [0.0; BATCH];
        Self {
            e_star: z,
            g_star: z,
            friction: z,
            rolling_friction: z,
            damping: z,
            stiffness_ratio_sqrt: z,
        }
    }
}

impl CoefficientRows {
    /// Sets slot `m` to the coefficients `c`. Inlined: the gathers call it per contact
    /// where the contacts' materials differ.
    #[inline(always)]
    pub fn set(&mut self, m: usize, c: &PairCoefficients) {
        self.e_star[m] = c.e_star;
        self.g_star[m] = c.g_star;
        self.friction[m] = c.friction;
        self.rolling_friction[m] = c.rolling_friction;
        self.damping[m] = c.damping;
        self.stiffness_ratio_sqrt[m] = c.stiffness_ratio_sqrt;
    }

    /// Sets every slot to the coefficients `c`.
    #[inline(always)]
    pub fn fill(&mut self, c: &PairCoefficients) {
        self.e_star.fill(c.e_star);
        self.g_star.fill(c.g_star);
        self.friction.fill(c.friction);
        self.rolling_friction.fill(c.rolling_friction);
        self.damping.fill(c.damping);
        self.stiffness_ratio_sqrt.fill(c.stiffness_ratio_sqrt);
    }
}

/// R* [m], m* [kg] and 1/R [1/m] of a batch of equal spheres.
#[derive(Clone, Copy, Default)]
struct SharedBody {
    r_eff: f64,
    m_eff: f64,
    inv_radius: f64,
}

impl SharedBody {
    /// Of equal spheres of radius `radius` [m] and mass `mass` [kg]: R* and m* by the
    /// harmonic means' own expressions, so the same bits as for unequal spheres.
    #[inline(always)]
    fn of(radius: f64, mass: f64) -> Self {
        Self {
            r_eff: radius * radius / (radius + radius),
            m_eff: mass * mass / (mass + mass),
            inv_radius: 1.0 / radius,
        }
    }
}

#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2])
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - b[1] * a[2],
        a[2] * b[0] - b[2] * a[0],
        a[0] * b[1] - b[0] * a[1],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{BodyMotion, ContactGeometry, ContactHistory, ContactLaws};
    use crate::material::{harmonic, Interaction, Material, PairCoefficients};
    use glam::DVec3;
    use rand::{Rng, SeedableRng};

    #[test]
    fn batch_matches_the_scalar_contact_laws_on_random_contacts() {
        // Random Table-1 contacts: overlaps up to 3 % of R, speeds up to 2 m/s, spins up to
        // 200 rad/s, histories up to and beyond the Coulomb cap so both branches are hit.
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
        let m = Material::fan2023();
        let c = PairCoefficients::new(&m, Some(&m), &Interaction::fan2023());
        let dt = 2.5e-6;
        let unit = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| {
            DVec3::new(
                rng.gen::<f64>() - 0.5,
                rng.gen::<f64>() - 0.5,
                rng.gen::<f64>() - 0.5,
            )
        };
        let mut batch = Batch::default();
        let mut cases = Vec::new();
        for k in 0..BATCH {
            let (ri, rj) = (
                1.5e-3 * (1.0 + 0.2 * rng.gen::<f64>()),
                1.5e-3 * (1.0 + 0.2 * rng.gen::<f64>()),
            );
            let (mi, mj) = (2500.0 * 4.18879 * ri.powi(3), 2500.0 * 4.18879 * rj.powi(3));
            let dir = unit(&mut rng).normalize();
            let overlap = 0.03 * ri.min(rj) * rng.gen::<f64>() + 1e-9;
            let d = dir * (ri + rj - overlap);
            let (vi, vj) = (4.0 * unit(&mut rng), 4.0 * unit(&mut rng));
            let (wi, wj) = (400.0 * unit(&mut rng), 400.0 * unit(&mut rng));
            // Zero history for a quarter of them: the fresh-contact path.
            let xi = if k % 4 == 0 {
                DVec3::ZERO
            } else {
                2e-5 * unit(&mut rng)
            };
            batch.set_pair_motion(k, (d, vi - vj), (wi, wj), xi);
            batch.radius[0][k] = ri;
            batch.radius[1][k] = rj;
            batch.mass[0][k] = mi;
            batch.mass[1][k] = mj;
            batch.coeff.set(k, &c);
            cases.push((d, ri, rj, mi, mj, vi, vj, wi, wj, xi));
        }
        batch.len = BATCH;
        batch.resolve_pairs(dt);
        let mut slid = 0;
        for (k, &(d, ri, rj, mi, mj, vi, vj, wi, wj, xi)) in cases.iter().enumerate() {
            let dist = d.length();
            let overlap = ri + rj - dist;
            let g = ContactGeometry {
                normal: d / dist,
                overlap,
                r_eff: harmonic(ri, rj),
                m_eff: harmonic(mi, mj),
                arm_i: ri - 0.5 * overlap,
                arm_j: rj - 0.5 * overlap,
                inertia: [0.4 * mi * ri * ri, 0.4 * mj * rj * rj],
                mass_radius2: [mi * ri * ri, mj * rj * rj],
                radius: [ri, rj],
            };
            let mut h = ContactHistory {
                tangential: xi,
                rolling: DVec3::ZERO,
                bonded: false,
            };
            let bi = BodyMotion {
                velocity: vi,
                omega: wi,
            };
            let bj = BodyMotion {
                velocity: vj,
                omega: wj,
            };
            let f = ContactLaws::default().resolve(&g, &bi, &bj, &c, &mut h, dt);
            let out = |v: &[[f64; BATCH]; 3]| DVec3::new(v[0][k], v[1][k], v[2][k]);
            // Same formulas with the operations regrouped in a few places (r_eff, 1/|d|):
            // agreement to a few ulps of the largest component, 1e-12 relative.
            let close = |a: DVec3, b: DVec3| {
                (a - b).length() <= 1e-12 * a.length().max(b.length()) + 1e-300
            };
            assert!(
                close(out(&batch.force), f.force),
                "force {k}: {:?} vs {:?}",
                out(&batch.force),
                f.force
            );
            assert!(close(out(&batch.torque_i), f.torque_i), "torque i {k}");
            assert!(close(out(&batch.torque_j), f.torque_j), "torque j {k}");
            assert!(close(out(&batch.xi), h.tangential), "history {k}");
            if (h.tangential - xi).length() > 0.0
                && 8.0 * c.g_star * (g.r_eff * overlap).sqrt() * h.tangential.length()
                    >= 0.999_999
                        * c.friction
                        * (4.0 / 3.0)
                        * c.e_star
                        * (g.r_eff * overlap).sqrt()
                        * overlap
            {
                slid += 1;
            }
        }
        assert!(
            slid > 0 && slid < BATCH,
            "both sticking and sliding contacts must be exercised ({slid} slid)"
        );
    }
}

#[cfg(test)]
mod uniform_tests {
    use super::*;
    use crate::material::{Interaction, Material, PairCoefficients};
    use rand::{Rng, SeedableRng};

    /// The radius [m] and mass [kg] of the equal spheres of [`equal_spheres`].
    const SPHERE: (f64, f64) = (1.5e-3, 2500.0 * 4.18879 * 1.5e-3 * 1.5e-3 * 1.5e-3);

    /// A full batch of random touching pairs of Table-1 spheres of [`SPHERE`].
    fn equal_spheres(seed: u64) -> Batch {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let m = Material::fan2023();
        let c = PairCoefficients::new(&m, Some(&m), &Interaction::fan2023());
        let (r, mass) = SPHERE;
        let mut batch = Batch::default();
        batch.fill_coefficients(&c);
        for k in 0..BATCH {
            let mut u = || rng.gen::<f64>() - 0.5;
            let dir = [u(), u(), u()];
            let len = dot(dir, dir).sqrt();
            let gap = 2.0 * r * (1.0 - 0.02 * (u() + 0.5));
            for (a, &x) in dir.iter().enumerate() {
                batch.d[a][k] = x / len * gap;
                batch.dv[a][k] = 2.0 * u();
                batch.omega[0][a][k] = 300.0 * u();
                batch.omega[1][a][k] = 300.0 * u();
                batch.xi[a][k] = 2e-5 * u();
            }
            batch.dist2[k] = gap * gap;
            batch.radius[0][k] = r;
            batch.radius[1][k] = r;
            batch.mass[0][k] = mass;
            batch.mass[1][k] = mass;
        }
        batch.len = BATCH;
        batch
    }

    #[test]
    fn equal_sphere_kernel_is_bit_identical_to_the_general_one() {
        // Same R*, m* expressions, so forces, torques and histories must agree exactly;
        // the overlap fraction (a reciprocal instead of a division) to one ulp.
        let (r, mass) = SPHERE;
        let mut batch = equal_spheres(3);
        let mut uniform = batch.clone();
        batch.resolve_pairs(2.5e-6);
        uniform.resolve_pairs_uniform(2.5e-6, r, mass);
        assert_eq!(batch.force, uniform.force);
        assert_eq!(batch.torque_i, uniform.torque_i);
        assert_eq!(batch.torque_j, uniform.torque_j);
        assert_eq!(batch.xi, uniform.xi);
        for (a, b) in batch.overlap_fraction.iter().zip(&uniform.overlap_fraction) {
            assert!((a - b).abs() <= f64::EPSILON * a.abs(), "{a} vs {b}");
        }
    }

    #[test]
    fn a_short_batch_resolves_its_contacts_as_a_full_one_whatever_lies_past_them() {
        // The passes run over whole vectors, past `len`: the slots there must change no
        // bit of the contacts before it. Exact equality, against the full batch, for every
        // length, with what lies past `len` made as bad as it can be (NaN, infinities,
        // zeros).
        let (r, mass) = SPHERE;
        let full = {
            let mut b = equal_spheres(8);
            b.resolve_pairs_uniform(2.5e-6, r, mass);
            b
        };
        let junk = [f64::NAN, f64::INFINITY, 0.0, -1e300, f64::NEG_INFINITY];
        for len in 1..BATCH {
            let mut short = equal_spheres(8);
            for k in len..BATCH {
                let x = junk[k % junk.len()];
                for a in 0..3 {
                    (short.d[a][k], short.dv[a][k], short.xi[a][k]) = (x, x, x);
                    (short.omega[0][a][k], short.omega[1][a][k]) = (x, x);
                }
                short.dist2[k] = x;
            }
            short.len = len;
            short.resolve_pairs_uniform(2.5e-6, r, mass);
            let bits = |b: &Batch| {
                let rows = b.force.iter().chain(&b.torque_i).chain(&b.torque_j);
                rows.chain(&b.xi)
                    .chain(std::iter::once(&b.overlap_fraction))
                    .flat_map(|row| row[..len].iter().map(|x| x.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&short), bits(&full), "batch of {len}");
        }
    }
}
