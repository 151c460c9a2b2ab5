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
//! Sliding has no closed form once the slip's direction turns; it is integrated in one of two
//! charts, with adaptive Dormand–Prince 8(5,3) steps (local error 1e-10 of the impact's scales):
//!
//! - in `p_z` while the slip `ρ = |u_t|` is not shrinking fast (`û·g > −½|g|`, `g = du_t/dp_z`),
//!   the step at most `ρ/|g|` (a radian of turn);
//! - in `σ = ln(ρ_s/ρ)` while it shrinks towards a stop: `dφ/dσ = (û × g)/(−û·g)` and `dp_z/dσ =
//!   ρ/(−û·g)` are smooth up to the stop (`σ → ∞`), where in `p_z` the friction direction turns
//!   ever faster and a fixed step straddles the stop. Once what is left of the slip is below 1e-11
//!   of the speed, or its direction has settled, the rest of the slip is a straight stop, closed
//!   form.
//!
//! Each event (end of compression, end of restitution) is located inside its step by regula falsi
//! on the step's length; once the slip has stopped, the rest (sticking, or the diverging ray) is
//! linear in `p_z` and finished in closed form. Stronge's law cannot create energy; round-off and the other two laws could, so the
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

/// Local error allowed in one adaptive step, relative to the impact's scales (the frictionless
/// compression impulse, the approach speed; radians for the slip direction).
const TOL: f64 = 1e-10;
/// Largest number of integration steps in one impact (a guard against jamming).
const MAX_STEPS: usize = 100_000;
/// An impulse beyond this many times the frictionless one is a jam (see [`collide`]).
const JAMMED: f64 = 1e6;
/// The slip is integrated in `σ = ln(ρ_s/|u_t|)` once `û·g < −ENTER |g|` (the slip shrinks at more
/// than half its largest rate), and back in `p_z` once `û·g > −LEAVE |g|` (hysteresis).
const ENTER: f64 = 0.5;
/// A slip below this fraction of the contact's speed has stopped (what is left of it would move
/// the impulse by about as much, relative).
const STOPPED: f64 = 1e-11;
const LEAVE: f64 = 0.25;

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
    /// The next step in `p_z` and in `σ` (each chart's step-size control goes on from where it left).
    h: f64,
    h_sigma: f64,
    /// The frictionless compression impulse `−u_z0/K_zz` and the speed `|u⁻|`: the scales of the
    /// error control.
    p_scale: f64,
    u_scale: f64,
    /// A slip this small has stopped (see [`STOPPED`]).
    stop_tol: f64,
    /// `dy/dp_z` at `y`, when the last step of [`slide_step`](Self::slide_step) left it at hand.
    slope_at_y: Option<[f64; 6]>,
}

/// How a stretch of sliding integrated in `σ` ended.
enum SigmaEnd {
    /// The impact ended while sliding.
    Ended,
    /// The slip stopped (`u_t = 0`).
    Stopped,
    /// The slip no longer shrinks fast enough for `σ`: go on in `p_z`.
    Turned,
}

impl Integration {
    fn new(k: DMat3, u0: DVec3, mu: f64, e: f64, law: RestitutionLaw) -> Self {
        let p_scale = -u0.z / k.z_axis.z;
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
            h: p_scale / 16.0,
            h_sigma: 0.25,
            p_scale,
            u_scale: u0.length(),
            stop_tol: STOPPED * (u0.z.abs() + DVec3::new(u0.x, u0.y, 0.0).length()),
            slope_at_y: None,
        }
    }

    /// Runs the impact to its end; the impulse in the contact frame.
    fn run(&mut self) -> DVec3 {
        for _ in 0..MAX_STEPS {
            let rho = norm2(self.y[0], self.y[1]);
            if self.mu == 0.0 || rho <= self.stop_tol {
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
            if !(self.p_z <= JAMMED * 2.0 * self.p_scale) {
                // a jam (see `collide`), or a NaN
                return self.impulse();
            }
            let (ux, uy) = (self.y[0] / rho, self.y[1] / rho);
            let g = slip_rate(&self.k, self.mu, ux, uy);
            let g_t = norm2(g.x, g.y);
            let shrink = ux * g.x + uy * g.y;
            if shrink < -ENTER * g_t {
                self.slope_at_y = None;
                match self.slide_sigma(rho) {
                    SigmaEnd::Ended => return self.impulse(),
                    SigmaEnd::Stopped => {
                        self.y[0] = 0.0;
                        self.y[1] = 0.0;
                    }
                    SigmaEnd::Turned => {}
                }
            } else if self.slide_step(rho, g_t) {
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
        self.advance_linear(xi, f64::INFINITY);
        self.impulse()
    }

    /// Advances with the tangential impulse growing as `dp_t/dp_z = ξ` (so that `du/dp_z = K (ξ,
    /// 1)` is constant and everything is closed form) by `max` in `p_z` or to the end of the
    /// impact, whichever comes first, ending compression on the way. Returns whether the impact
    /// ended.
    fn advance_linear(&mut self, xi: (f64, f64), max: f64) -> bool {
        let du = self.k * DVec3::new(xi.0, xi.1, 1.0);
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
        let mut max = max;
        if self.compressing {
            let dp = (-self.y[2] / dz).max(0.0);
            if dp > max {
                advance(self, max);
                return false;
            }
            advance(self, dp);
            self.y[2] = 0.0;
            self.end_compression();
            max -= dp;
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
        let dp = dp.max(0.0);
        if dp > max {
            advance(self, max);
            return false;
        }
        advance(self, dp);
        true
    }

    fn end_compression(&mut self) {
        self.compressing = false;
        self.w_c = self.y[5];
        self.p_c = self.p_z;
    }

    /// The event that ends the current phase, from the normal velocity `u_z`, the work `W` and
    /// `p_z`: negative before it, ≥ 0 at and after it.
    fn event(&self, u_z: f64, w: f64, p_z: f64) -> f64 {
        if self.compressing {
            return u_z;
        }
        match self.law {
            RestitutionLaw::Stronge => w - (1.0 - self.e * self.e) * self.w_c,
            RestitutionLaw::Newton => u_z + self.e * self.u_z0,
            RestitutionLaw::Poisson => p_z - (1.0 + self.e) * self.p_c,
        }
    }

    /// One adaptive step of sliding in `p_z`, the slip `ρ = |u_t|` shrinking at less than half its
    /// largest rate `|g|`: the step is at most `ρ / |g|`, over which the slip's direction may turn
    /// by a radian. The end of the phase inside it is located. Returns whether the impact ended.
    fn slide_step(&mut self, rho: f64, g_t: f64) -> bool {
        let h_max = if g_t > 0.0 { rho / g_t } else { f64::INFINITY };
        let (p, u, w) = (self.p_scale, self.u_scale, self.p_scale * self.u_scale);
        let scales = [u, u, u, p, p, w];
        let (k, mu, y0) = (self.k, self.mu, self.y);
        let f = |_: f64, y: &[f64; 6]| slope(&k, mu, y);
        let k1 = self.slope_at_y.take().unwrap_or_else(|| f(0.0, &y0));
        let Some(Accepted { taken, y: y1, slope: k_end, h_next }) =
            adaptive_step(&f, 0.0, &y0, &k1, self.h.min(h_max), &scales)
        else {
            // no step the error control accepts (NaN): leave the impulse as it is
            self.p_z = f64::INFINITY;
            return true;
        };
        self.h = h_next;
        let p_z0 = self.p_z;
        let event = |s: f64, y: &[f64; 6]| self.event(y[2], y[5], p_z0 + s);
        if event(taken, &y1) >= 0.0 {
            let (root, y_root) = locate_event(&f, &y0, &k1, taken, &y1, event);
            self.y = y_root;
            self.p_z += root;
            if self.compressing {
                self.y[2] = self.y[2].max(0.0);
                self.end_compression();
                return false;
            }
            return true;
        }
        self.y = y1;
        self.p_z += taken;
        self.slope_at_y = Some(k_end);
        false
    }

    /// Sliding with `σ = ln(ρ_s/ρ)` as the independent variable, from the slip `ρ_s`, while the
    /// slip shrinks (`a = û·g < 0`): with the slip's direction `φ`,
    ///
    /// `dφ/dσ = (û × g)/(−a)`, `dp_z/dσ = ρ/(−a)`, and `dp_t/dσ = −μ û dp_z/dσ`,
    /// `du_z/dσ = (K (−μ û, 1))_z dp_z/dσ`, `dW/dσ = u_z dp_z/dσ`,
    ///
    /// all smooth up to the stop (`σ → ∞`, where `dp_z/dσ` vanishes like `e^{−σ}`), where in `p_z`
    /// the slip's direction turns ever faster. Integrated until what is left of the slip (`ρ/(−a)`
    /// in `p_z`) is negligible, or until the direction has settled and the rest is a straight
    /// stop, finished in closed form.
    fn slide_sigma(&mut self, rho_s: f64) -> SigmaEnd {
        let (k, mu) = (self.k, self.mu);
        let (p, u) = (self.p_scale, self.u_scale);
        // z = [cos φ, sin φ, ρ/ρ_s, u_z, p_x, p_y, p_z, W]: the direction as a unit vector and the
        // slip's decay e^{−σ} carried along, so that a stage needs no trigonometry or exponential
        let mut z = [self.y[0] / rho_s, self.y[1] / rho_s, 1.0, self.y[2], self.y[3], self.y[4], self.p_z, self.y[5]];
        let mut scales = [1.0, 1.0, 1.0, u, p, p, p, p * u];
        let f = |_: f64, z: &[f64; 8]| {
            let (c, s, decay) = (z[0], z[1], z[2]);
            let du = slip_rate(&k, mu, c, s);
            let per = 1.0 / -(c * du.x + s * du.y);
            let turn = (c * du.y - s * du.x) * per;
            let q = rho_s * decay * per;
            [-turn * s, turn * c, -decay, du.z * q, -mu * c * q, -mu * s * q, q, z[3] * q]
        };
        let mut k1 = None;
        let write_back = |s: &mut Self, z: &[f64; 8]| {
            let rho = rho_s * z[2];
            s.y = [rho * z[0], rho * z[1], z[3], z[4], z[5], z[7]];
            s.p_z = z[6];
        };
        for _ in 0..MAX_STEPS {
            // back on the unit circle when the steps' truncation has moved it off
            let norm = norm2(z[0], z[1]);
            if (norm - 1.0).abs() > 1e-9 {
                (z[0], z[1]) = (z[0] / norm, z[1] / norm);
                k1 = None;
            }
            let (c, s) = (z[0], z[1]);
            let du = slip_rate(&k, mu, c, s);
            let (minus_a, turn) = (-(c * du.x + s * du.y), c * du.y - s * du.x);
            if minus_a < LEAVE * norm2(du.x, du.y) {
                write_back(self, &z);
                return SigmaEnd::Turned;
            }
            // what is left of the slip, in p_z, were it to stop straight from here; stopping
            // straight errs by about that times the direction's turn per unit σ in the impulse,
            // and the slip times that turn in the velocity after (exact on a ray, where the slip's
            // direction stays)
            let left = rho_s * z[2] / minus_a;
            let straight_err = left * turn.abs();
            if rho_s * z[2] <= self.stop_tol || straight_err <= (1e-12 * p * minus_a).min(self.stop_tol) {
                write_back(self, &z);
                if self.advance_linear((-mu * c, -mu * s), left) {
                    return SigmaEnd::Ended;
                }
                return SigmaEnd::Stopped;
            }
            // an error δφ in the direction moves what is left of the impulse by about `left δφ`,
            // a relative error in the decay by `left δ`
            let weight = p / left;
            (scales[0], scales[1], scales[2]) = (weight, weight, z[2] * weight);
            let slope_z = k1.take().unwrap_or_else(|| f(0.0, &z));
            let Some(Accepted { taken, y: z1, slope: k_end, h_next }) =
                adaptive_step(&f, 0.0, &z, &slope_z, self.h_sigma, &scales)
            else {
                write_back(self, &z);
                self.p_z = f64::INFINITY;
                return SigmaEnd::Ended;
            };
            self.h_sigma = h_next;
            let event = |_: f64, z: &[f64; 8]| self.event(z[3], z[7], z[6]);
            if event(taken, &z1) >= 0.0 {
                let (_, z_root) = locate_event(&f, &z, &slope_z, taken, &z1, event);
                write_back(self, &z_root);
                if !self.compressing {
                    return SigmaEnd::Ended;
                }
                self.y[2] = self.y[2].max(0.0);
                self.end_compression();
                z = z_root;
                z[3] = self.y[2];
                continue;
            }
            z = z1;
            k1 = Some(k_end);
        }
        write_back(self, &z);
        SigmaEnd::Stopped
    }
}

/// `√(x² + y²)` (the slips and rates here are far from overflow; `f64::hypot` costs several times more).
fn norm2(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

/// `du/dp_z = K (−μ û, 1)` while sliding along the unit `û = (u_x, u_y)` (contact frame); its
/// tangential part is the slip's rate `g(û)`.
fn slip_rate(k: &DMat3, mu: f64, ux: f64, uy: f64) -> DVec3 {
    *k * DVec3::new(-mu * ux, -mu * uy, 1.0)
}

/// `dy/dp_z` while sliding, `y = [u_x, u_y, u_z, p_x, p_y, W]`.
fn slope(k: &DMat3, mu: f64, y: &[f64; 6]) -> [f64; 6] {
    let len = norm2(y[0], y[1]);
    let (ux, uy) = if len > 0.0 { (y[0] / len, y[1] / len) } else { (0.0, 0.0) };
    let du = slip_rate(k, mu, ux, uy);
    [du.x, du.y, du.z, -mu * ux, -mu * uy, y[2]]
}

/// One step of [`dop853`]: the eighth-order solution, the two embedded error estimates (fifth- and
/// third-order differences) and the slope at the end (the next step's first stage).
struct Step<const N: usize> {
    y: [f64; N],
    err5: [f64; N],
    err3: [f64; N],
    slope: [f64; N],
}

/// The Dormand–Prince 8(5,3) tableau, as DOP853 has it: the nodes `c` of stages 2–12, each stage's
/// row of `a` (pairs `(j, a_j)` of the earlier stages it combines, zeros left out), the
/// eighth-order weights `b`, and the weights of the differences from the fifth- and third-order
/// solutions.
mod dop853_tableau {
    pub const C: [f64; 11] = [
        0.05260015195876773,
        0.0789002279381516,
        0.1183503419072274,
        0.2816496580927726,
        0.3333333333333333,
        0.25,
        0.3076923076923077,
        0.6512820512820513,
        0.6,
        0.8571428571428571,
        1.0,
    ];
    pub const A: [&[(usize, f64)]; 11] = [
        &[(0, 0.05260015195876773)],
        &[(0, 0.0197250569845379), (1, 0.0591751709536137)],
        &[(0, 0.02958758547680685), (2, 0.08876275643042054)],
        &[(0, 0.2413651341592667), (2, -0.8845494793282861), (3, 0.924834003261792)],
        &[(0, 0.037037037037037035), (3, 0.17082860872947386), (4, 0.12546768756682242)],
        &[(0, 0.037109375), (3, 0.17025221101954405), (4, 0.06021653898045596), (5, -0.017578125)],
        &[
            (0, 0.03709200011850479),
            (3, 0.17038392571223998),
            (4, 0.10726203044637328),
            (5, -0.015319437748624402),
            (6, 0.008273789163814023),
        ],
        &[
            (0, 0.6241109587160757),
            (3, -3.3608926294469414),
            (4, -0.868219346841726),
            (5, 27.59209969944671),
            (6, 20.154067550477894),
            (7, -43.48988418106996),
        ],
        &[
            (0, 0.47766253643826434),
            (3, -2.4881146199716677),
            (4, -0.590290826836843),
            (5, 21.230051448181193),
            (6, 15.279233632882423),
            (7, -33.28821096898486),
            (8, -0.020331201708508627),
        ],
        &[
            (0, -0.9371424300859873),
            (3, 5.186372428844064),
            (4, 1.0914373489967295),
            (5, -8.149787010746927),
            (6, -18.52006565999696),
            (7, 22.739487099350505),
            (8, 2.4936055526796523),
            (9, -3.0467644718982196),
        ],
        &[
            (0, 2.273310147516538),
            (3, -10.53449546673725),
            (4, -2.0008720582248625),
            (5, -17.9589318631188),
            (6, 27.94888452941996),
            (7, -2.8589982771350235),
            (8, -8.87285693353063),
            (9, 12.360567175794303),
            (10, 0.6433927460157636),
        ],
    ];
    pub const B: &[(usize, f64)] = &[
        (0, 0.054293734116568765),
        (5, 4.450312892752409),
        (6, 1.8915178993145003),
        (7, -5.801203960010585),
        (8, 0.3111643669578199),
        (9, -0.1521609496625161),
        (10, 0.20136540080403034),
        (11, 0.04471061572777259),
    ];
    pub const E5: &[(usize, f64)] = &[
        (0, 0.01312004499419488),
        (5, -1.2251564463762044),
        (6, -0.4957589496572502),
        (7, 1.6643771824549864),
        (8, -0.35032884874997366),
        (9, 0.3341791187130175),
        (10, 0.08192320648511571),
        (11, -0.022355307863886294),
    ];
    pub const E3: &[(usize, f64)] = &[
        (0, -0.18980075407240762),
        (5, 4.450312892752409),
        (6, 1.8915178993145003),
        (7, -5.801203960010585),
        (8, -0.4226823213237919),
        (9, -0.1521609496625161),
        (10, 0.20136540080403034),
        (11, 0.02265179219836082),
    ];
}

/// `Σ_j w_j k_j[i]` over a row of the tableau, summed left to right.
#[inline(always)]
fn combine<const N: usize>(row: &[(usize, f64)], k: &[[f64; N]; 12], i: usize) -> f64 {
    let (j0, w0) = row[0];
    row[1..].iter().fold(w0 * k[j0][i], |sum, &(j, w)| sum + w * k[j][i])
}

/// One step of the Dormand–Prince 8(5,3) pair (P. J. Prince, J. R. Dormand, *High order embedded
/// Runge–Kutta formulae*, J. Comput. Appl. Math. 7, 1981; Hairer, Nørsett, Wanner, *Solving
/// Ordinary Differential Equations I*, §II.10, the code DOP853) of `dy/dt = f(t, y)` from `(t, y)`
/// with `k1 = f(t, y)` given: twelve stages, the eighth-order solution, its differences from the
/// embedded fifth- and third-order ones (combined into one error estimate by [`adaptive_step`]),
/// and the slope at the end (the next step's `k1`; one evaluation more, not a stage of the pair).
/// Eighth order, because the impact asks for 1e-10 of its scales (against the 5(4) pair it replaced,
/// the legged trots' collisions took half the time: Solo-12's 3.46 → 1.88 µs per step). Written out here, not taken from an ODE crate, because the impact
/// needs it on a fixed-size state with no allocation, inside its own event location and change of
/// variable.
fn dop853<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    y: &[f64; N],
    k1: &[f64; N],
    h: f64,
) -> Step<N> {
    use dop853_tableau::{A, B, C, E3, E5};
    let mut k = [[0.0; N]; 12];
    let mut stage = [0.0; N];
    k[0] = *k1;
    // stage by stage with constant indices, so that each row's weights and stages are known when
    // compiling (a loop over the rows left them to be read at run time: 5 % slower)
    macro_rules! stage {
        ($($s:literal)*) => {$(
            for i in 0..N {
                stage[i] = y[i] + h * combine(A[$s - 1], &k, i);
            }
            k[$s] = f(t + C[$s - 1] * h, &stage);
        )*};
    }
    stage!(1 2 3 4 5 6 7 8 9 10 11);
    let mut y1 = [0.0; N];
    let (mut err5, mut err3) = ([0.0; N], [0.0; N]);
    for i in 0..N {
        y1[i] = y[i] + h * combine(B, &k, i);
        err5[i] = h * combine(E5, &k, i);
        err3[i] = h * combine(E3, &k, i);
    }
    let slope = f(t + h, &y1);
    Step { y: y1, err5, err3, slope }
}

/// A step [`adaptive_step`] accepted.
struct Accepted<const N: usize> {
    /// The step taken, the state after it and the slope there.
    taken: f64,
    y: [f64; N],
    slope: [f64; N],
    /// The step to try next.
    h_next: f64,
}

/// One accepted step of [`dop853`] from `(t, y)` (slope `k1` there), trying `h` first: the error, measured against
/// `scales` component by component, at most [`TOL`]; smaller steps (the usual controller,
/// `h ← 0.9 h (TOL/err)^{1/8}`) until it is. The error is DOP853's blend of the two estimates,
/// `err = e₅² / √(e₅² + 0.01 e₃²)`: the fifth-order difference, kept from overestimating on
/// large steps by the third-order one. Returns the step taken, the state after it and the
/// step to try next; `None` if no step is accepted (a NaN).
fn adaptive_step<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    t: f64,
    y: &[f64; N],
    k1: &[f64; N],
    h: f64,
    scales: &[f64; N],
) -> Option<Accepted<N>> {
    let mut h = h;
    for _ in 0..200 {
        let step = dop853(f, t, y, k1, h);
        let norm = |e: &[f64; N]| e.iter().zip(scales).map(|(e, s)| (e / s).abs()).fold(0.0, f64::max);
        let (e5, e3) = (norm(&step.err5), norm(&step.err3));
        let denominator = (e5 * e5 + 0.01 * e3 * e3).sqrt();
        let ratio = if denominator > 0.0 { e5 * e5 / denominator / TOL } else { e5 / TOL };
        if ratio <= 1.0 {
            let grow = if ratio > 0.0 { (0.9 * eighth_root_inverse(ratio)).clamp(0.2, 6.0) } else { 6.0 };
            return Some(Accepted { taken: h, y: step.y, slope: step.slope, h_next: h * grow });
        }
        // a NaN ratio (a stage where the slip stops in σ) shrinks the step too
        h *= if ratio.is_finite() { (0.9 * eighth_root_inverse(ratio)).clamp(0.1, 0.5) } else { 0.25 };
    }
    None
}

/// `r^(−1/8)` for the step-size controller, by three square roots instead of `powf` (the
/// factor needs no more than a few digits).
#[inline]
fn eighth_root_inverse(r: f64) -> f64 {
    1.0 / r.sqrt().sqrt().sqrt()
}

/// Where in the accepted step `taken` from `y` (slope `k1`; `y_end` after it) the event function
/// `event(s, state after s)` first reaches zero: the step to it and the state there, each trial a
/// single [`dop853`] step from `y` (shorter than the accepted one, so as accurate).
fn locate_event<const N: usize>(
    f: &impl Fn(f64, &[f64; N]) -> [f64; N],
    y: &[f64; N],
    k1: &[f64; N],
    taken: f64,
    y_end: &[f64; N],
    event: impl Fn(f64, &[f64; N]) -> f64,
) -> (f64, [f64; N]) {
    let at = |s: f64| if s == taken { *y_end } else { dop853(f, 0.0, y, k1, s).y };
    let root = first_root(taken, |s| event(s, &at(s)));
    (root, at(root))
}

/// The first `s ∈ (0, h]` where `f(s)` reaches zero, with `f < 0` at `s = 0` and `f ≥ 0` at
/// `s = h`: the upper end of a bracket no wider than `10⁻¹⁴ h` (so that `f ≥ 0` there). Regula
/// falsi with the Illinois rule (the retained end's value halved when the same end is kept
/// twice), which converges superlinearly on a smooth `f` and never leaves the bracket.
fn first_root(h: f64, f: impl Fn(f64) -> f64) -> f64 {
    let (mut a, mut fa) = (0.0, f(0.0));
    let (mut b, mut fb) = (h, f(h));
    if !(fa < 0.0) {
        // the event is already at the start (Stronge's law with e = 0 ends restitution at once)
        return 0.0;
    }
    if !(fb >= 0.0) {
        return h;
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
        let fc = f(c);
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
    b
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The tableau is fifth order: on `y' = y`, halving the step divides the error after one unit
    /// by about 2⁵; the embedded estimate of one step's error (the fourth-order solution's) shrinks
    /// like h⁵.
    /// The pair is eighth order: on the pendulum `θ'' = −sin θ` (nonlinear, so that every order
    /// condition counts), halving the step divides the error after four units of time by about
    /// 2⁸; the fifth-order estimate of one step's error shrinks like h⁶ and the third-order one
    /// like h⁴ (each the difference from the eighth-order solution).
    #[test]
    fn dormand_prince_853_is_eighth_order() {
        let f = |_: f64, y: &[f64; 2]| [y[1], -y[0].sin()];
        let y0 = [1.0, 0.5];
        let solve = |n: usize| {
            let h = 4.0 / n as f64;
            let mut y = y0;
            for i in 0..n {
                y = dop853(&f, i as f64 * h, &y, &f(0.0, &y), h).y;
            }
            y
        };
        let exact = solve(4096);
        let error = |n: usize| {
            let y = solve(n);
            (y[0] - exact[0]).abs().max((y[1] - exact[1]).abs())
        };
        let ratio = error(8) / error(16);
        assert!((ratio.log2() - 8.0).abs() < 0.5, "order {:.2}", ratio.log2());
        let estimates = |h: f64| {
            let step = dop853(&f, 0.0, &y0, &f(0.0, &y0), h);
            (step.err5[0].abs().max(step.err5[1].abs()), step.err3[0].abs().max(step.err3[1].abs()))
        };
        let ((a5, a3), (b5, b3)) = (estimates(0.4), estimates(0.2));
        assert!(((a5 / b5).log2() - 6.0).abs() < 0.5, "fifth-order estimate's order {:.2}", (a5 / b5).log2());
        assert!(((a3 / b3).log2() - 4.0).abs() < 0.5, "third-order estimate's order {:.2}", (a3 / b3).log2());
        // the slope handed on is the slope at the end (first same as last)
        let step = dop853(&f, 0.0, &y0, &f(0.0, &y0), 0.3);
        assert_eq!(step.slope, f(0.3, &step.y));
    }
}
