//! Elementary frame rotations (the SOFA R₁, R₂, R₃ convention): `rot_x(φ)`
//! rotates the *axes* by +φ about x, so a fixed vector's components change as
//! v′ = R₁(φ)·v.

use glam::{DMat3, DVec3};

/// Matrix from its rows.
#[inline]
pub(crate) fn from_rows(r0: [f64; 3], r1: [f64; 3], r2: [f64; 3]) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(r0[0], r1[0], r2[0]),
        DVec3::new(r0[1], r1[1], r2[1]),
        DVec3::new(r0[2], r1[2], r2[2]),
    )
}

/// R₁(φ): axes rotated by φ about x.
#[inline]
pub(crate) fn rot_x(phi: f64) -> DMat3 {
    let (s, c) = (libm::sin(phi), libm::cos(phi));
    from_rows([1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c])
}

/// R₂(θ): axes rotated by θ about y.
#[inline]
pub(crate) fn rot_y(theta: f64) -> DMat3 {
    let (s, c) = (libm::sin(theta), libm::cos(theta));
    from_rows([c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c])
}

/// R₃(ψ): axes rotated by ψ about z.
#[inline]
pub(crate) fn rot_z(psi: f64) -> DMat3 {
    let (s, c) = (libm::sin(psi), libm::cos(psi));
    from_rows([c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0])
}
