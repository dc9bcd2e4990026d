use glam::Vec3;
use himmel_skymodel::atmosphere::reference::{self, ReferenceConfig};
use himmel_skymodel::atmosphere::*;
use himmel_skymodel::spectrum::BandWeights;
fn main() {
    let p = AtmosphereParams::default();
    let w = BandWeights::solar();
    let args: Vec<usize> = std::env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let c = LutConfig { multiscatter_n: args[0], multiscatter_dirs: args[1], multiscatter_steps: args[2], sky_view_steps: args[3], orders: args[4] as u32, ..LutConfig::default() };
    let luts = AtmosphereLuts::compute(&p, &c);
    for &alt in &[-4.0f32, -8.0] {
        let s = alt.to_radians().sin();
        let sun = SkyView::sun_local(s);
        let mut line = format!("alt {alt}");
        for &(e, az) in &[(90.0f32, 0.0f32), (30.0, 90.0), (5.0, 0.0), (5.0, 180.0), (20.0,180.0)] {
            let (e, az) = (e.to_radians(), az.to_radians());
            let d = Vec3::new(e.cos() * az.cos(), e.cos() * az.sin(), e.sin());
            let lut = w.to_y(&SkyView::transfer(&luts, luts.medium.bottom, d, sun, c.sky_view_steps));
            let rc = ReferenceConfig { paths: 4000, ..Default::default() };
            let rf = w.to_y(&reference::radiance(&luts.medium, luts.medium.bottom, d, sun, &rc));
            line += &format!(" | {lut:.3e} / {rf:.3e} = {:.2}", lut / rf);
        }
        println!("{line}");
    }
}
