//! Quadrille's geometric model: a boundary representation (B-rep) made of
//! corners, curves and faces, each carrying exact geometry behind a trait.
//!
//! Every other crate sees CAD only through these types: the OpenCASCADE
//! importer (`occt` crate) and the discrete model built from triangle meshes
//! both produce a [`Model`]. Coordinates are `f64`; ids are newtypes.

pub mod model;
pub mod primitives;
pub mod slivers;
pub mod traits;
pub mod vec3;

pub use model::{
    Bounds2, Corner, CornerId, CornerUv, CurveEntity, CurveId, CurveUse, Face, FaceId, Loop, Model,
    ModelError,
};
pub use traits::{nearest_period, nearest_periodic_uv, Curve, Curve2d, Surface, SurfaceDerivs};
pub use vec3::Vec3;
