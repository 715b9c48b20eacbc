//! Everything about what is drawn: the scene data model, built-in procedural scenes, the
//! OBJ/MTL loader, the deterministic camera and the forward renderer that draws a scene into
//! the targets a technique asks for.

pub mod camera;
pub mod model;
pub mod obj;
pub mod procedural;
pub mod renderer;
pub mod source;

pub use model::{
    AlphaMode, CameraRig, DirectionalLight, Material, Mesh, Scene, Spin, TextureImage, Vertex,
};
