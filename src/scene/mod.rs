//! Everything about what is drawn: the scene data model, built-in procedural scenes, the
//! OBJ/MTL and glTF 2.0 loaders, the deterministic camera and the forward renderer that draws a scene into
//! the targets a technique asks for.

pub mod camera;
pub mod framing;
pub mod gltf;
pub mod interior;
pub mod model;
pub mod motion;
pub mod obj;
pub mod procedural;
pub mod renderer;
pub mod source;

pub use camera::CameraRig;
pub use model::{
    AlphaMode, DirectionalLight, Filter, Material, Mesh, NormalDetail, Scene, SceneView, Spin,
    TextureImage, TextureSampler, Vertex, Wrap,
};
pub use motion::Motion;
