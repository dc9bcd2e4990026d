//! Evaluation of the VSOP87D series (Bretagnon & Francou 1988; Meeus,
//! Astronomical Algorithms 2nd ed., ch. 32).
//!
//! A coordinate X ∈ {L, B, R} is Σ_α τ^α Σ_k A_k cos(B_k + C_k τ), τ in Julian
//! millennia (TDB ≈ TT) from J2000.0 (Meeus eq. 32.1–32.2). The outer sum over α
//! is evaluated by Horner's rule, so τ's powers are never formed explicitly.

/// One series X_α: its terms sorted by decreasing amplitude, and how many
/// leading terms the truncated evaluation keeps.
pub(super) struct Vsop87Series {
    /// `[A, B, C]` per term.
    pub(super) terms: &'static [[f64; 3]],
    /// Number of leading terms kept by `Series::Truncated`.
    pub(super) truncated: usize,
}

/// The L, B, R series of one body, indexed by the power α of τ (0, 1, 2, …).
pub(super) struct Vsop87Body {
    pub(super) l: &'static [Vsop87Series],
    pub(super) b: &'static [Vsop87Series],
    pub(super) r: &'static [Vsop87Series],
}

#[inline]
fn sum_terms(terms: &[[f64; 3]], tau: f64) -> f64 {
    let mut sum = 0.0;
    for &[a, b, c] in terms {
        sum += a * libm::cos(b + c * tau);
    }
    sum
}

#[inline]
fn coordinate(series: &[Vsop87Series], tau: f64, full: bool) -> f64 {
    let mut acc = 0.0;
    for s in series.iter().rev() {
        let n = if full { s.terms.len() } else { s.truncated };
        acc = acc * tau + sum_terms(&s.terms[..n], tau);
    }
    acc
}

/// (L rad, B rad, R AU) of `body` at `tau` millennia from J2000.0; L unreduced.
pub(super) fn evaluate(body: &Vsop87Body, tau: f64, full: bool) -> (f64, f64, f64) {
    (
        coordinate(body.l, tau, full),
        coordinate(body.b, tau, full),
        coordinate(body.r, tau, full),
    )
}

/// Number of terms evaluated for (truncated, full) series of `body`.
#[cfg(test)]
pub(super) fn term_counts(body: &Vsop87Body) -> (usize, usize) {
    let all = body.l.iter().chain(body.b).chain(body.r);
    all.fold((0, 0), |(t, f), s| (t + s.truncated, f + s.terms.len()))
}
