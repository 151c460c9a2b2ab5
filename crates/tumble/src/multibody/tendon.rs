//! Fixed tendons: linear couplings of one-coordinate joints, MuJoCo's `<tendon><fixed>`.
//!
//! Reference: E. Todorov, MuJoCo documentation, *Modeling* ("Tendons": fixed tendons) and
//! *Computation* (passive forces: tendon spring-dampers). A fixed tendon has a length that is a
//! linear function of the joint positions, and so a constant Jacobian `J_t` (a row over the
//! velocity coordinates):
//!
//! ```text
//! L(q) = L₀ + Σ_i c_i q_i          (L₀ = Σ_i c_i ref_i: MuJoCo's length is in qpos = q + ref)
//! L̇    = J_t v = Σ_i c_i v_i
//! ```
//!
//! A force `f` along the tendon (its spring and damper, an actuator on it, a limit) is the joint
//! force `τ = J_tᵀ f`, i.e. `τ_i += c_i f`. Its spring-damper is
//!
//! ```text
//! f = −k (L − L_s) − d L̇       (k: stiffness, d: damping, L_s: spring length)
//! ```
//!
//! with a dead band `[L_lo, L_hi]` when two spring lengths are given (no force inside, the spring
//! from the nearer end outside). Its potential energy is `½ k (L − L_s)²` (`½ k` times the squared
//! distance to the band).
//!
//! A tendon term's joint must be a revolute, continuous or prismatic joint (one coordinate).

use super::model::MultibodyModel;

/// One joint of a fixed tendon: `coef · q` adds to the length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TendonTerm {
    /// The joint's body (index into [`MultibodyModel::bodies`]).
    pub body: usize,
    /// Its position coordinate (index into `q`).
    pub q_index: usize,
    /// Its velocity coordinate (index into `v`).
    pub v_index: usize,
    /// `c_i` (m/rad or dimensionless).
    pub coef: f64,
}

/// A fixed tendon: `L(q) = L₀ + Σ c_i q_i`, with an optional spring-damper and length range.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedTendon {
    pub name: String,
    /// The joints and their coefficients (each joint at most once).
    pub terms: Vec<TendonTerm>,
    /// `L₀` (the length at `q = 0`).
    pub offset: f64,
    /// Spring stiffness `k ≥ 0` (N/m along the tendon).
    pub stiffness: f64,
    /// The spring's rest length `[L_lo, L_hi]` (equal for a plain spring).
    pub spring_length: (f64, f64),
    /// Damping `d ≥ 0` (N·s/m along the tendon).
    pub damping: f64,
    /// The length range `[lo, hi]` when the tendon is limited.
    pub range: Option<(f64, f64)>,
}

impl FixedTendon {
    /// `L(q)`.
    #[inline]
    pub fn length(&self, q: &[f64]) -> f64 {
        self.offset + self.terms.iter().map(|t| t.coef * q[t.q_index]).sum::<f64>()
    }

    /// `L̇ = J_t v`.
    #[inline]
    pub fn rate(&self, v: &[f64]) -> f64 {
        self.terms.iter().map(|t| t.coef * v[t.v_index]).sum()
    }

    /// `τ += J_tᵀ f`.
    #[inline]
    pub fn add_force(&self, f: f64, tau: &mut [f64]) {
        for t in &self.terms {
            tau[t.v_index] += t.coef * f;
        }
    }

    /// How far `L` is outside the spring's rest band (0 inside it).
    #[inline]
    pub fn spring_stretch(&self, length: f64) -> f64 {
        let (lo, hi) = self.spring_length;
        if length < lo {
            length - lo
        } else if length > hi {
            length - hi
        } else {
            0.0
        }
    }

    /// Whether it exerts a passive force (a spring or a damper).
    pub fn is_passive(&self) -> bool {
        self.stiffness != 0.0 || self.damping != 0.0
    }
}

/// Adds every tendon's spring-damper force at `(q, v)` to `tau`: `τ += J_tᵀ (−k (L − L_s) − d L̇)`
/// (lengths checked by the caller).
pub(crate) fn add_passive_unchecked(model: &MultibodyModel, q: &[f64], v: &[f64], tau: &mut [f64]) {
    for t in model.tendons.iter().filter(|t| t.is_passive()) {
        let mut f = 0.0;
        if t.stiffness != 0.0 {
            f -= t.stiffness * t.spring_stretch(t.length(q));
        }
        if t.damping != 0.0 {
            f -= t.damping * t.rate(v);
        }
        t.add_force(f, tau);
    }
}

/// The tendons' spring energy `½ Σ k (L − L_s)²` (J).
pub(crate) fn spring_energy_unchecked(model: &MultibodyModel, q: &[f64]) -> f64 {
    model
        .tendons
        .iter()
        .filter(|t| t.stiffness != 0.0)
        .map(|t| {
            let s = t.spring_stretch(t.length(q));
            0.5 * t.stiffness * s * s
        })
        .sum()
}
