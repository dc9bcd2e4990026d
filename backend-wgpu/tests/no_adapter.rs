//! Without any adapter of the allowed backends, `WgpuRenderer::new`
//! returns `WgpuError::NoAdapter` instead of panicking. This test binary
//! holds only this test: it restricts `WGPU_BACKEND` for its process.

use himmel_wgpu::{WgpuError, WgpuRenderer};

#[test]
fn absent_backend_gives_a_typed_error() {
    // DX12 exists only on Windows; Metal only on Apple systems.
    let absent = if cfg!(windows) { "metal" } else { "dx12" };
    std::env::set_var("WGPU_BACKEND", absent);
    match WgpuRenderer::new(None) {
        Err(WgpuError::NoAdapter(m)) => assert!(!m.is_empty()),
        Err(e) => panic!("expected NoAdapter, got {e}"),
        Ok(r) => panic!("expected no adapter, got {:?}", r.adapter_info()),
    }
    let e: himmel_skymodel::RenderError = WgpuError::NoAdapter("x".into()).into();
    assert!(e.to_string().contains("no wgpu adapter"));
}
