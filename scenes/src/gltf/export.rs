//! Export: any scene as a `.glb` (see `to_glb`).
