//! The impulse of one collision at one contact point, by integrating through the impact.
//!
//! References: B. Mirtich, *Impulse-based dynamic simulation of rigid body systems*, PhD thesis,
//! UC Berkeley 1996, §4.2–4.4 (the collision matrix, integration with the normal impulse as the
//! independent variable, sliding, sticking and the diverging ray); W. J. Stronge, *Impact
//! Mechanics*, §2.4 and §5 (the energetic coefficient of restitution); R. Baber (2011) on the
//! sticking case where `|ξ| > μ` (sliding resumes along a diverging ray, which must be found among
//! the roots, not assumed).
//!
//! Bodies A and B touch at `p`, unit normal `n` from A to B. The relative contact velocity is
//! `u = (v_b + ω_b × r_b) − (v_a + ω_a × r_a)` and an impulse `P` on B (`−P` on A) changes it by
//! `Δu = K P`, `K = (1/m_a + 1/m_b) 1 − r̃_b I_b⁻¹ r̃_b − r̃_a I_a⁻¹ r̃_a` (world frame; symmetric
//! positive definite). In the contact frame `(t1, t2, n)`, with the normal impulse `p_z` as "time":
//!
//! - sliding, `u_t ≠ 0`: `du/dp_z = K (−μ u_t/|u_t|, 1)` (Coulomb friction opposes sliding);
//! - sticking, `u_t = 0`: the direction `(ξ, 1)` that keeps `u_t = 0` solves `K_tt ξ = −k_tn`;
//!   if `|ξ| ≤ μ` sticking lasts and `du/dp_z = K (ξ, 1)` is constant; otherwise sliding resumes
//!   along the unit `s` with `−μ K_tt s + k_tn = λ s`, `λ > 0`, and stays on that ray, so that
//!   `du/dp_z = K (−μ s, 1)` is constant too;
//! - the normal work `W = ∫ u_z dp_z` is negative while compressing (`u_z < 0`); compression ends
//!   at `u_z = 0` with `W_c`. Stronge's law ends the impact when `W = (1 − e²) W_c`; Newton's when
//!   `u_z = −e u_z⁻`; Poisson's when `p_z = (1 + e) p_z(compression)`.
//!
//! Sliding is integrated with classical RK4 in `p_z`, steps of 1/256 of the frictionless
//! compression impulse, each event (end of compression, the slip's stop, end of restitution)
//! located by regula falsi; once the slip has stopped, the rest (sticking, or the diverging ray)
//! is linear in `p_z` and finished in closed form. Stronge's law cannot create energy; round-off and the other two laws could, so the
//! result is checked: if `ΔT = u⁻·P + ½ Pᵀ K P > 0` the impulse is scaled back to `ΔT = 0`.

use crate::math::{DMat3, DVec3};

/// Which law ends the restitution phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RestitutionLaw {
    /// Work in restitution = `e²` × work in compression (never creates energy). The default.
    #[default]
    Stronge,
    /// Normal velocity after = `−e` × normal velocity before.
    Newton,
    /// Normal impulse in restitution = `e` × normal impulse in compression.
    Poisson,
}

impl RestitutionLaw {
    /// Names as written in scene files.
    pub const NAMES: [&'static str; 3] = ["stronge", "newton", "poisson"];

    /// Parses a scene file's name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "stronge" => Some(Self::Stronge),
            "newton" => Some(Self::Newton),
            "poisson" => Some(Self::Poisson),
            _ => None,
        }
    }
}

/// The outcome of one collision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// The impulse on body B (A receives `−impulse`), world frame (N·s).
    pub impulse_world: DVec3,
    /// Kinetic energy dissipated, `−ΔT ≥ 0` (J).
    pub energy_lost: f64,
}

/// Integration steps per frictionless compression impulse.
const STEPS: f64 = 256.0;
/// Largest number of integration steps in one impact (a guard against jamming).
const MAX_STEPS: usize = 100_000;
/// An impulse beyond this many times the frictionless one is a jam (see [`collide`]).
const JAMMED: f64 = 1e6;

/// The impulse of a collision with relative contact velocity `u_world` (m/s, world frame,
/// approaching: `u·n < 0`), collision matrix `k_world` (1/kg, world frame), unit normal `n` (A → B),
/// friction `mu ≥ 0` and restitution `e ∈ [0, 1]` under `law`. `None` if the contact is not
/// approaching or `K` is not usable (both bodies fixed).
pub fn collide(k_world: DMat3, n: DVec3, u_world: DVec3, mu: f64, e: f64, law: RestitutionLaw) -> Option<Impact> {
    let approach = u_world.dot(n);
    if approach.is_nan() || approach >= 0.0 || !k_world.is_finite() || !u_world.is_finite() {
        return None;
    }
    let (t1, t2) = tangent_basis(n);
    let frame = DMat3::from_cols(t1, t2, n);
    let k = frame.transpose() * k_world * frame;
    if k.z_axis.z.is_nan() || k.z_axis.z <= 0.0 {
        return None;
    }
    let u0 = frame.transpose() * u_world;
    let mut impact = Integration::new(k, u0, mu.max(0.0), e.clamp(0.0, 1.0), law);
    let mut p_contact = impact.run();
    // a collision matrix that is only positive semi-definite (a robot at a singular pose) can jam the
    // frictional integration: the impulse then grows along a direction K does not see, without
    // end. Its effect is then meaningless; the frictionless impact is always well posed
    // (`p_z = (1 + e) p_c` at most, `p_c = −u_z/K_zz` the compression impulse)
    let compression = -u0.z / k.z_axis.z;
    if !p_contact.is_finite() || p_contact.length() > JAMMED * 2.0 * compression {
        p_contact = Integration::new(k, u0, 0.0, e.clamp(0.0, 1.0), law).run();
    }
    let mut p = frame * p_contact;
    // ΔT = u⁻·P + ½ PᵀKP: scale back if round-off (or Newton's / Poisson's law) would create energy
    let quad = p.dot(k_world * p);
    let lin = u_world.dot(p);
    if lin + 0.5 * quad > 0.0 && quad > 0.0 {
        p *= (-2.0 * lin / quad).clamp(0.0, 1.0);
    }
    let delta_t = u_world.dot(p) + 0.5 * p.dot(k_world * p);
    p.is_finite().then_some(Impact { impulse_world: p, energy_lost: (-delta_t).max(0.0) })
}

/// Two unit tangents completing `n` to a right-handed frame `(t1, t2, n)`.
pub fn tangent_basis(n: DVec3) -> (DVec3, DVec3) {
    let t1 = n.any_orthonormal_vector();
    (t1, n.cross(t1))
}

/// The impact's state in the contact frame, with `p_z` the independent variable.
struct Integration {
    k: DMat3,
    mu: f64,
    e: f64,
    law: RestitutionLaw,
    /// `[u_x, u_y, u_z, p_x, p_y, W]`.
    y: [f64; 6],
    p_z: f64,
    u_z0: f64,
    compressing: bool,
    w_c: f64,
    p_c: f64,
    h: f64,
    /// The nominal step (1/256 of the frictionless compression impulse) and the velocity scale.
    h0: f64,
    u_scale: f64,
}

impl Integration {
    fn new(k: DMat3, u0: DVec3, mu: f64, e: f64, law: RestitutionLaw) -> Self {
        let h = -u0.z / k.z_axis.z / STEPS;
        Self {
            k,
            mu,
            e,
            law,
            y: [u0.x, u0.y, u0.z, 0.0, 0.0, 0.0],
            p_z: 0.0,
            u_z0: u0.z,
            compressing: true,
            w_c: 0.0,
            p_c: 0.0,
            h,
            h0: h,
            u_scale: u0.length(),
        }
    }

    /// Runs the impact to its end; the impulse in the contact frame.
    fn run(&mut self) -> DVec3 {
        let scale = self.u_z0.abs() + DVec3::new(self.y[0], self.y[1], 0.0).length();
        let stick_tol = 1e-12 * scale;
        for _ in 0..MAX_STEPS {
            let ut = (self.y[0], self.y[1]);
            if self.mu == 0.0 || (ut.0 * ut.0 + ut.1 * ut.1).sqrt() <= stick_tol {
                match self.stick_direction() {
                    Ok(xi) => return self.finish_linear(xi),
                    // sliding resumes along the diverging ray s, on which it stays: `du_t/dp_z =
                    // g(s) = λ s`, so the friction `−μ s` and `du/dp_z` hold to the end, as while
                    // sticking. (Integrating it instead, from a slip of zero, is unstable across
                    // the ray: the friction direction turns at a rate `~ μ |K_tt| / |u_t|` that has
                    // no bound while the slip is small, and RK4 let round-off grow to errors of
                    // 1e-4 in the impulse.)
                    Err(s) => return self.finish_linear((-self.mu * s.0, -self.mu * s.1)),
                }
            }
            if self.slide_step() {
                return self.impulse();
            }
        }
        self.impulse()
    }

    fn impulse(&self) -> DVec3 {
        DVec3::new(self.y[3], self.y[4], self.p_z)
    }

    /// Sticking analysis: `Ok(ξ)` if sticking is stable (`|ξ| ≤ μ`, frictionless: `ξ = 0`), else
    /// `Err(s)`, the diverging ray along which sliding resumes.
    fn stick_direction(&self) -> Result<(f64, f64), (f64, f64)> {
        if self.mu == 0.0 {
            return Ok((0.0, 0.0));
        }
        let k = &self.k;
        // K_tt ξ = −k_tn (columns of glam matrices: k.col(j)[i] = K_ij)
        let (a, b, c, d) = (k.x_axis.x, k.y_axis.x, k.x_axis.y, k.y_axis.y);
        let (r0, r1) = (-k.z_axis.x, -k.z_axis.y);
        let det = a * d - b * c;
        let xi = ((d * r0 - b * r1) / det, (a * r1 - c * r0) / det);
        if (xi.0 * xi.0 + xi.1 * xi.1).sqrt() <= self.mu * (1.0 + 1e-12) {
            return Ok(xi);
        }
        Err(self.diverging_ray())
    }

    /// The unit `s` with `g(s) = −μ K_tt s + k_tn = λ s`, `λ > 0` (Baber 2011: sample the circle
    /// for every root of `g(s) × s = 0`, keep the one with the largest `λ`).
    fn diverging_ray(&self) -> (f64, f64) {
        let k = &self.k;
        let g = |phi: f64| {
            let (s0, s1) = (phi.cos(), phi.sin());
            let g0 = -self.mu * (k.x_axis.x * s0 + k.y_axis.x * s1) + k.z_axis.x;
            let g1 = -self.mu * (k.x_axis.y * s0 + k.y_axis.y * s1) + k.z_axis.y;
            (g0 * s1 - g1 * s0, g0 * s0 + g1 * s1)
        };
        const SAMPLES: usize = 72;
        let step = std::f64::consts::TAU / SAMPLES as f64;
        let mut best = (f64::NEG_INFINITY, 0.0);
        for i in 0..SAMPLES {
            let (mut lo, mut hi) = (i as f64 * step, (i + 1) as f64 * step);
            let (f_lo, f_hi) = (g(lo).0, g(hi).0);
            if f_lo * f_hi > 0.0 {
                continue;
            }
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (g(mid).0 > 0.0) == (f_lo > 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let phi = 0.5 * (lo + hi);
            let lambda = g(phi).1;
            if lambda > best.0 {
                best = (lambda, phi);
            }
        }
        (best.1.cos(), best.1.sin())
    }

    /// Stable sticking (or no friction): `du/dp_z = K (ξ, 1)` is constant; finish in closed form.
    fn finish_linear(&mut self, xi: (f64, f64)) -> DVec3 {
        let dir = DVec3::new(xi.0, xi.1, 1.0);
        let du = self.k * dir;
        let dz = du.z.max(1e-300);
        let advance = |s: &mut Self, dp: f64| {
            let uz = s.y[2];
            s.y[5] += uz * dp + 0.5 * dz * dp * dp;
            s.y[0] += du.x * dp;
            s.y[1] += du.y * dp;
            s.y[2] += dz * dp;
            s.y[3] += xi.0 * dp;
            s.y[4] += xi.1 * dp;
            s.p_z += dp;
        };
        if self.compressing {
            let dp = (-self.y[2] / dz).max(0.0);
            advance(self, dp);
            self.y[2] = 0.0;
            self.end_compression();
        }
        let dp = match self.law {
            RestitutionLaw::Stronge => {
                // W + u_z Δp + ½ d_z Δp² = W_end
                let w_end = (1.0 - self.e * self.e) * self.w_c;
                let uz = self.y[2];
                let disc = (uz * uz + 2.0 * dz * (w_end - self.y[5])).max(0.0);
                (-uz + disc.sqrt()) / dz
            }
            RestitutionLaw::Newton => (-self.e * self.u_z0 - self.y[2]) / dz,
            RestitutionLaw::Poisson => (1.0 + self.e) * self.p_c - self.p_z,
        };
        advance(self, dp.max(0.0));
        self.impulse()
    }

    fn end_compression(&mut self) {
        self.compressing = false;
        self.w_c = self.y[5];
        self.p_c = self.p_z;
    }

    /// The event that ends the current phase: negative before it, ≥ 0 at and after it.
    fn event(&self, y: &[f64; 6], p_z: f64) -> f64 {
        if self.compressing {
            return y[2];
        }
        match self.law {
            RestitutionLaw::Stronge => y[5] - (1.0 - self.e * self.e) * self.w_c,
            RestitutionLaw::Newton => y[2] + self.e * self.u_z0,
            RestitutionLaw::Poisson => p_z - (1.0 + self.e) * self.p_c,
        }
    }

    /// One sliding step (an event found inside it shortens it). Returns whether the impact ended.
    ///
    /// Two events end a step early: the phase's end ([`event`](Self::event) reaches 0) and the stop
    /// of the slip, which is taken where either RK4 or the Euler predictor reverses `u_t` (RK4's
    /// stages straddling the stop average the discontinuous friction direction and can miss it).
    /// The predictor's stop is a closed form, `(u_t0 + s k1_t)·u_t0 = 0`; the other two are roots
    /// of smooth functions of the step, found by regula falsi (Illinois) in a bracket.
    fn slide_step(&mut self) -> bool {
        let ut0 = (self.y[0], self.y[1]);
        let k1 = self.slope(&self.y);
        // the Euler predictor's stop: s = |u_t0|² / (−k1_t·u_t0) when the slip decreases
        let decrease = -(k1[0] * ut0.0 + k1[1] * ut0.1);
        let euler_stop = if decrease > 0.0 { (ut0.0 * ut0.0 + ut0.1 * ut0.1) / decrease } else { f64::INFINITY };
        // u_t·u_t0 ≤ 0: RK4 reversed the slip
        let slip = move |y: &[f64; 6]| y[0] * ut0.0 + y[1] * ut0.1;
        let full = rk4(self, &self.y, self.h);
        let phase_ends = self.event(&full, self.p_z + self.h) >= 0.0;
        if !phase_ends && slip(&full) > 0.0 && euler_stop > self.h {
            self.y = full;
            self.p_z += self.h;
            // after a shortened step near a stop, grow back to the nominal step
            self.h = (2.0 * self.h).min(self.h0);
            return false;
        }
        // the first event in (0, h]: below the predictor's stop, where RK4's slip reverses or the
        // phase ends, whichever comes first
        let hi = self.h.min(euler_stop);
        let y_hi = if hi < self.h { rk4(self, &self.y, hi) } else { full };
        let mut stop = (euler_stop <= self.h).then_some(hi);
        if slip(&y_hi) <= 0.0 {
            let (lo, _) = self.first_root(hi, &y_hi, |_, y, _| -slip(y));
            stop = Some(lo);
        }
        let end = (self.event(&y_hi, self.p_z + hi) >= 0.0)
            .then(|| self.first_root(hi, &y_hi, |s, y, h| s.event(y, s.p_z + h)))
            .filter(|&(_, hi_end)| stop.is_none_or(|lo_stop| hi_end <= lo_stop));
        if let Some((_, hi)) = end {
            self.y = rk4(self, &self.y, hi);
            self.p_z += hi;
            if self.compressing {
                self.y[2] = self.y[2].max(0.0);
                self.end_compression();
                return false;
            }
            return true;
        }
        // sliding stops at lo. RK4's last stage would sit on the stop, where the friction
        // direction is round-off: step RK4 to 0.999 lo, where every stage still has a direction,
        // then Euler over the last thousandth (the work `W = ∫ u_z dp_z` with its second-order
        // term, exact while `du_z/dp_z` holds), and let the sticking analysis decide what follows
        let lo = stop.unwrap_or(hi);
        let y_near = rk4(self, &self.y, 0.999 * lo);
        let slope = self.slope(&y_near);
        let last = 0.001 * lo;
        self.y = std::array::from_fn(|i| y_near[i] + last * slope[i]);
        self.y[5] += 0.5 * slope[2] * last * last;
        self.p_z += lo;
        if (self.y[0] * self.y[0] + self.y[1] * self.y[1]).sqrt() > 1e-11 * self.u_scale && self.h > 1e-12 * self.h0 {
            // the Euler predictor's stop was early (a curved slip path): go on in smaller steps
            self.h *= 1.0 / 16.0;
            return false;
        }
        self.h = self.h0;
        self.y[0] = 0.0;
        self.y[1] = 0.0;
        false
    }

    /// The bracket `(lo, hi)` of a root of `f(state after a step s)`, with `f < 0` at `s = 0` and
    /// `f ≥ 0` at `s = h` (`y_h`: the state after the step `h`, already at hand): `f < 0` at `lo`, `f ≥ 0` at `hi`, `hi − lo ≤ 10⁻¹⁴ h`. Regula falsi with
    /// the Illinois rule (the retained end's value halved when the same end is kept twice), which
    /// converges superlinearly on a smooth `f` and never leaves the bracket.
    fn first_root(&self, h: f64, y_h: &[f64; 6], f: impl Fn(&Self, &[f64; 6], f64) -> f64) -> (f64, f64) {
        let (mut a, mut fa) = (0.0, f(self, &self.y, 0.0));
        let (mut b, mut fb) = (h, f(self, y_h, h));
        if !(fa < 0.0) {
            // the event is already at the start (Stronge's law with e = 0 ends restitution at once)
            return (0.0, 0.0);
        }
        if !(fb >= 0.0) {
            return (0.0, h);
        }
        let mut kept = 0i8;
        for _ in 0..100 {
            if b - a <= 1e-14 * h {
                break;
            }
            let mut c = (a * fb - b * fa) / (fb - fa);
            if !(c > a && c < b) {
                c = 0.5 * (a + b);
            }
            let fc = f(self, &rk4(self, &self.y, c), c);
            if fc >= 0.0 {
                (b, fb) = (c, fc);
                if kept == 1 {
                    fa *= 0.5;
                }
                kept = 1;
            } else {
                (a, fa) = (c, fc);
                if kept == -1 {
                    fb *= 0.5;
                }
                kept = -1;
            }
        }
        (a, b)
    }

    /// `dy/dp_z` while sliding.
    fn slope(&self, y: &[f64; 6]) -> [f64; 6] {
        let len = (y[0] * y[0] + y[1] * y[1]).sqrt();
        let (fx, fy) = if len > 0.0 { (-self.mu * y[0] / len, -self.mu * y[1] / len) } else { (0.0, 0.0) };
        let du = self.k * DVec3::new(fx, fy, 1.0);
        [du.x, du.y, du.z, fx, fy, y[2]]
    }
}

/// One classical Runge–Kutta step of size `h` in `p_z`.
fn rk4(s: &Integration, y: &[f64; 6], h: f64) -> [f64; 6] {
    let add = |a: &[f64; 6], k: &[f64; 6], f: f64| std::array::from_fn::<f64, 6, _>(|i| a[i] + f * k[i]);
    let k1 = s.slope(y);
    let k2 = s.slope(&add(y, &k1, 0.5 * h));
    let k3 = s.slope(&add(y, &k2, 0.5 * h));
    let k4 = s.slope(&add(y, &k3, h));
    std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// The collision matrix `K` (1/kg, world frame) of a contact at offsets `r_a`, `r_b` (m, world frame)
/// from the centres of mass, given the inverse masses (1/kg) and world inverse inertias (1/(kg·m²));
/// a fixed body has inverse mass and inertia zero.
pub fn collision_matrix(
    inv_mass_a: f64,
    inv_inertia_a: DMat3,
    r_a: DVec3,
    inv_mass_b: f64,
    inv_inertia_b: DMat3,
    r_b: DVec3,
) -> DMat3 {
    use crate::math::skew;
    let (sa, sb) = (skew(r_a), skew(r_b));
    DMat3::from_diagonal(DVec3::splat(inv_mass_a + inv_mass_b)) - sb * inv_inertia_b * sb - sa * inv_inertia_a * sa
}
