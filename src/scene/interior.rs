//! Interiors: whether a loaded model encloses the centre of its own bounds (a room, a building,
//! a Cornell box) and, if it does, an inside view to open it with, instead of the orbit
//! framing that would show its outer walls.
//!
//! # The test
//! [`Enclosure::measure`] casts rays from the centre of the model's bounding box in
//! [`MAX_RAYS`] directions spread evenly over the sphere and records, for each, the nearest
//! surface it meets (either side of a triangle), whether that surface faces back towards the
//! centre (its winding's normal points at the centre: the inside of a room), and whether it
//! lies on the bounding box's shell (a wall, floor or ceiling). The model is an interior
//! ([`Enclosure::is_interior`]) when most rays meet a surface (the centre is enclosed) and
//! either
//! - most of the surfaces met face the centre (a room modelled with inward normals, as
//!   building interiors like Sponza are), or
//! - many rays end on the bounds' shell and a few escape through its side (a shell of walls
//!   with one side open: a set built to be looked into, like the Cornell box, whatever way
//!   its normals point; a vessel open at the top is an object).
//!
//! An ordinary closed object (a bunny, a teapot) encloses its centre too, but its surfaces
//! face away from it and lie inside the bounds rather than on them; a closed box with outward
//! faces is an object (a crate), and the same box with inward faces a room.
//!
//! # The inside view
//! [`inside_view`] looks level at the centre of the bounds from mid-height. A model with an
//! open side (a face of the bounds that the rays from the centre pass through, like the
//! Cornell box's) is seen through that side from just far enough in front of it that the
//! opening fills the view: the classic Cornell box view, which shows every wall, the floor,
//! the ceiling and what stands inside. Otherwise the eye stands inside, near one end of the
//! longest horizontal axis, looking along it; a surface between the centre and that spot
//! moves the eye closer to the centre. The view does not orbit (turning about the centre
//! would take the eye through the walls); `--camera-motion pan` turns it in place.

use glam::Vec3;

use super::{CameraRig, Scene};

/// Most ray directions cast from the centre.
pub const MAX_RAYS: usize = 128;
/// Fewest ray directions (very large models).
const MIN_RAYS: usize = 32;
/// Ray-triangle tests the measurement may spend; larger models get fewer rays.
const TEST_BUDGET: usize = 40_000_000;
/// Share of rays that must meet a surface for the centre to count as enclosed.
const ENCLOSED: f32 = 0.6;
/// Share of the surfaces met that must face the centre for an inward-facing room.
const INWARD: f32 = 0.6;
/// Share of rays that must end on the bounds' shell for a shell of walls (the Cornell box's
/// blocks take a third of the view from its centre; closed objects reach about a fifth).
const SHELL: f32 = 0.3;
/// Share of rays that must escape for the shell to have an opening.
const OPENING: f32 = 0.05;
/// A hit at least this fraction of the way to the bounding box counts as on its shell.
const ON_SHELL: f32 = 0.9;
/// How far from the centre towards the opening (or the end of the room) the eye stands, as a
/// fraction of the way to the bounds.
const EYE_REACH: f32 = 0.9;
/// An opening this close to a horizontal axis, in degrees, is taken to face along it.
const SNAP_DEGREES: f32 = 15.0;
/// Points per side of the grid a face of the bounds is checked for openness with.
const FACE_GRID: usize = 6;
/// Share of those points the centre must see for the face to be open.
const OPEN_FACE: f32 = 0.6;
/// How much larger than the opening the view in front of it is.
const FACE_MARGIN: f32 = 1.05;
/// Vertical field of view of an inside view, in degrees.
const FOV_Y_DEGREES: f32 = 45.0;

/// What rays cast from the centre of a model's bounds met.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Enclosure {
    /// The centre of the bounds.
    pub center: Vec3,
    /// The bounds.
    pub bounds: (Vec3, Vec3),
    /// Rays cast.
    pub rays: usize,
    /// Rays that met a surface.
    pub hits: usize,
    /// Hits on a surface facing the centre.
    pub inward: usize,
    /// Hits on the bounds' shell.
    pub on_shell: usize,
    /// Sum of the directions of the rays that escaped.
    pub escaped_towards: Vec3,
    /// The outward axis of the face of the bounds that is open, if one is.
    pub open_side: Option<Vec3>,
}

/// The nearest surface a ray met.
#[derive(Clone, Copy)]
struct Hit {
    t: f32,
    inward: bool,
}

/// Directions spread evenly over the sphere (a Fibonacci lattice, which has no direction
/// along a coordinate axis, so rays do not run along axis-aligned walls).
fn directions(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5.0_f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - (i as f32 + 0.5) / n as f32 * 2.0;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f32 + 0.1;
            Vec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// Distance along `dir` from `origin` (inside the box) to the box's boundary.
fn to_bounds(origin: Vec3, dir: Vec3, (lo, hi): (Vec3, Vec3)) -> f32 {
    let mut t = f32::INFINITY;
    for axis in 0..3 {
        let d = dir[axis];
        if d > 1e-9 {
            t = t.min((hi[axis] - origin[axis]) / d);
        } else if d < -1e-9 {
            t = t.min((lo[axis] - origin[axis]) / d);
        }
    }
    t.max(0.0)
}

/// Where a ray meets a triangle (either side), Möller-Trumbore: the distance, when ahead.
fn intersect(origin: Vec3, dir: Vec3, [a, b, c]: [Vec3; 3], epsilon: f32) -> Option<f32> {
    let e1 = b - a;
    let e2 = c - a;
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv;
    (t > epsilon).then_some(t)
}

/// Every triangle of the scene at frame 0, as corner positions.
fn triangles(scene: &Scene) -> impl Iterator<Item = [Vec3; 3]> + '_ {
    scene.meshes.iter().flat_map(|mesh| {
        mesh.indices.chunks_exact(3).filter_map(|t| {
            let corner = |i: u32| {
                mesh.vertices
                    .get(i as usize)
                    .map(|v| Vec3::from(v.position))
            };
            Some([corner(t[0])?, corner(t[1])?, corner(t[2])?])
        })
    })
}

/// The nearest surfaces along `dirs` from `origin`.
fn cast(scene: &Scene, origin: Vec3, dirs: &[Vec3], epsilon: f32) -> Vec<Option<Hit>> {
    let mut nearest: Vec<Option<Hit>> = vec![None; dirs.len()];
    for tri in triangles(scene) {
        let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        for (dir, best) in dirs.iter().zip(nearest.iter_mut()) {
            if let Some(t) = intersect(origin, *dir, tri, epsilon)
                && best.is_none_or(|b| t < b.t)
            {
                *best = Some(Hit {
                    t,
                    // The winding's normal points back along the ray: the face is seen from
                    // its front, from the centre.
                    inward: normal.dot(*dir) < 0.0,
                });
            }
        }
    }
    nearest
}

impl Enclosure {
    /// Casts the rays (see the module docs); `None` for a scene without triangles.
    pub fn measure(scene: &Scene) -> Option<Self> {
        let bounds = scene.bounds()?;
        let count = triangles(scene).count();
        if count == 0 {
            return None;
        }
        let rays = (TEST_BUDGET / count).clamp(MIN_RAYS, MAX_RAYS);
        let center = (bounds.0 + bounds.1) * 0.5;
        let epsilon = (bounds.1 - bounds.0).max_element() * 1e-6;
        let dirs = directions(rays);
        let hits = cast(scene, center, &dirs, epsilon);
        let mut enclosure = Self {
            center,
            bounds,
            rays,
            hits: 0,
            inward: 0,
            on_shell: 0,
            escaped_towards: Vec3::ZERO,
            open_side: None,
        };
        for (dir, hit) in dirs.iter().zip(&hits) {
            match hit {
                Some(hit) => {
                    enclosure.hits += 1;
                    enclosure.inward += usize::from(hit.inward);
                    let shell = to_bounds(center, *dir, bounds);
                    enclosure.on_shell += usize::from(hit.t >= ON_SHELL * shell);
                }
                None => enclosure.escaped_towards += *dir,
            }
        }
        enclosure.open_side = enclosure
            .escape_axis()
            .filter(|axis| open_fraction(scene, center, bounds, *axis, epsilon) >= OPEN_FACE);
        Some(enclosure)
    }

    /// Rays that met nothing.
    pub fn escaped(&self) -> usize {
        self.rays - self.hits
    }

    /// Whether the model is an interior (see the module docs).
    pub fn is_interior(&self) -> bool {
        let rays = self.rays as f32;
        let enclosed = self.hits as f32 >= ENCLOSED * rays;
        let inward = self.inward as f32 >= INWARD * self.hits as f32;
        let open_shell = self.on_shell as f32 >= SHELL * rays && self.open_side.is_some();
        enclosed && (inward || open_shell)
    }

    /// The horizontal axis the escaped rays left along, when enough escaped and their mean
    /// direction is within [`SNAP_DEGREES`] of that axis (not only through a missing roof).
    fn escape_axis(&self) -> Option<Vec3> {
        if (self.escaped() as f32) < OPENING * self.rays as f32 {
            return None;
        }
        let mean = self.escaped_towards.try_normalize()?;
        let axis = if mean.x.abs() >= mean.z.abs() {
            Vec3::new(mean.x.signum(), 0.0, 0.0)
        } else {
            Vec3::new(0.0, 0.0, mean.z.signum())
        };
        (mean.dot(axis) >= SNAP_DEGREES.to_radians().cos()).then_some(axis)
    }
}

/// The share of a grid of points on the face of the bounds facing `axis` that the centre
/// sees unobstructed.
fn open_fraction(
    scene: &Scene,
    center: Vec3,
    (lo, hi): (Vec3, Vec3),
    axis: Vec3,
    epsilon: f32,
) -> f32 {
    let n = FACE_GRID;
    let mut points = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (a, b) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let along = |k: usize, f: f32| lo[k] + (hi[k] - lo[k]) * f;
            let face = if axis.x > 0.0 {
                hi.x
            } else if axis.x < 0.0 {
                lo.x
            } else {
                0.0
            };
            let point = if axis.x != 0.0 {
                Vec3::new(face, along(1, a), along(2, b))
            } else {
                let face = if axis.z > 0.0 { hi.z } else { lo.z };
                Vec3::new(along(0, b), along(1, a), face)
            };
            points.push(point);
        }
    }
    let dirs: Vec<Vec3> = points
        .iter()
        .map(|p| (*p - center).normalize_or_zero())
        .collect();
    let hits = cast(scene, center, &dirs, epsilon);
    let open = points
        .iter()
        .zip(&hits)
        .filter(|(p, hit)| hit.is_none_or(|h| h.t >= (**p - center).length() * 0.999))
        .count();
    open as f32 / (n * n) as f32
}

/// The inside view of an interior (see the module docs); `None` when the scene has no
/// triangles or is no interior.
pub fn inside_view(scene: &Scene) -> Option<CameraRig> {
    let enclosure = Enclosure::measure(scene).filter(Enclosure::is_interior)?;
    let (lo, hi) = enclosure.bounds;
    let center = enclosure.center;
    let size = hi - lo;
    let radius = size.length() * 0.5;
    let near = radius * 0.01;
    let half_fov = (FOV_Y_DEGREES.to_radians() * 0.5).tan();
    if let Some(axis) = enclosure.open_side {
        // In front of the opening, far enough back for it to fill the view.
        let across = if axis.x != 0.0 { size.z } else { size.x };
        let back = size.y.max(across) * 0.5 * FACE_MARGIN / half_fov;
        let eye = center + axis * (to_bounds(center, axis, enclosure.bounds) + back);
        return CameraRig::looking_at(eye, center, FOV_Y_DEGREES, near, 0.0);
    }
    // Inside, near one end of the longest horizontal axis.
    let towards_eye = if size.x >= size.z {
        Vec3::NEG_X
    } else {
        Vec3::NEG_Z
    };
    let mut reach = to_bounds(center, towards_eye, enclosure.bounds) * EYE_REACH;
    let epsilon = size.max_element() * 1e-6;
    if let Some(Some(hit)) = cast(scene, center, &[towards_eye], epsilon).first() {
        // Something stands between the centre and that spot: stop short of it.
        reach = reach.min(hit.t * EYE_REACH);
    }
    let extent = size.max_element().max(1e-6);
    let eye = center + towards_eye * reach;
    // Look at the centre, or (eye at the centre) a little way across the room.
    let look_at = eye - towards_eye * reach.max(extent * 0.25);
    CameraRig::looking_at(eye, look_at, FOV_Y_DEGREES, near, 0.0)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::scene::{Material, Mesh, Vertex};

    /// A scene of one mesh with `triangles` (no normals needed: the test reads the winding).
    pub(crate) fn scene_of(name: &str, triangles: &[[Vec3; 3]]) -> Scene {
        let vertices: Vec<Vertex> = triangles
            .iter()
            .flatten()
            .map(|p| Vertex {
                position: p.to_array(),
                normal: [0.0, 1.0, 0.0],
                uv: [0.0, 0.0],
            })
            .collect();
        let mut scene = Scene::empty(name);
        scene.materials.push(Material::default());
        scene.meshes.push(Mesh {
            name: name.to_owned(),
            indices: (0..vertices.len() as u32).collect(),
            vertices,
            material: 0,
            spin: None,
        });
        scene
    }

    /// The faces of the box `lo`..`hi`, wound to face outwards (or inwards), leaving out the
    /// faces whose outward normal is in `open`.
    pub(crate) fn box_faces(lo: Vec3, hi: Vec3, inward: bool, open: &[Vec3]) -> Vec<[Vec3; 3]> {
        let mut out = Vec::new();
        for axis in 0..3 {
            for side in [-1.0f32, 1.0] {
                let mut normal = Vec3::ZERO;
                normal[axis] = side;
                if open.contains(&normal) {
                    continue;
                }
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corner = |a: bool, b: bool| {
                    let mut p = Vec3::ZERO;
                    p[axis] = if side > 0.0 { hi[axis] } else { lo[axis] };
                    p[u] = if a { hi[u] } else { lo[u] };
                    p[v] = if b { hi[v] } else { lo[v] };
                    p
                };
                let quad = [
                    corner(false, false),
                    corner(true, false),
                    corner(true, true),
                    corner(false, true),
                ];
                for tri in [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]] {
                    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                    let faces_out = n.dot(normal) > 0.0;
                    out.push(if faces_out != inward {
                        tri
                    } else {
                        [tri[0], tri[2], tri[1]]
                    });
                }
            }
        }
        out
    }

    /// A closed UV sphere wound outwards.
    fn sphere(center: Vec3, radius: f32) -> Vec<[Vec3; 3]> {
        let (rings, segments) = (12, 24);
        let point = |i: usize, j: usize| {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            center
                + radius
                    * Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.cos(),
                        theta.sin() * phi.sin(),
                    )
        };
        let mut out = Vec::new();
        for i in 0..rings {
            for j in 0..segments {
                let (a, b, c, d) = (
                    point(i, j),
                    point(i + 1, j),
                    point(i + 1, j + 1),
                    point(i, j + 1),
                );
                for tri in [[a, b, c], [a, c, d]] {
                    let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                    let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
                    if n.length() < 1e-9 {
                        continue;
                    }
                    out.push(if n.dot(centroid - center) > 0.0 {
                        tri
                    } else {
                        [tri[0], tri[2], tri[1]]
                    });
                }
            }
        }
        out
    }

    const LO: Vec3 = Vec3::new(-3.0, 0.0, -2.0);
    const HI: Vec3 = Vec3::new(3.0, 3.0, 2.0);

    #[test]
    fn a_box_with_inward_faces_is_a_room_and_with_outward_faces_an_object() {
        let room = scene_of("room", &box_faces(LO, HI, true, &[]));
        let measured = Enclosure::measure(&room).unwrap();
        assert_eq!(measured.hits, measured.rays, "closed");
        assert!(measured.is_interior(), "{measured:?}");
        let rig = inside_view(&room).expect("an inside view");
        let pose = crate::scene::camera::OrbitPose::at_frame(&rig, 0);
        let eye = pose.eye();
        assert!(
            eye.cmpgt(LO).all() && eye.cmplt(HI).all(),
            "the eye {eye} is inside the room"
        );
        // Along the longest horizontal axis (x), level, towards the centre.
        let forward = (pose.target - eye).normalize();
        assert!(forward.x > 0.99, "looks along x: {forward}");
        assert!(eye.x < -2.0, "from near one end: {eye}");
        assert_eq!(rig.orbit_degrees_per_frame, 0.0);

        let crate_box = scene_of("crate", &box_faces(LO, HI, false, &[]));
        let measured = Enclosure::measure(&crate_box).unwrap();
        assert!(!measured.is_interior(), "{measured:?}");
        assert!(inside_view(&crate_box).is_none());
    }

    #[test]
    fn closed_objects_keep_the_orbit_framing() {
        let ball = scene_of("ball", &sphere(Vec3::new(1.0, 2.0, 3.0), 1.5));
        let measured = Enclosure::measure(&ball).unwrap();
        assert_eq!(
            measured.hits, measured.rays,
            "the centre is inside the ball"
        );
        assert!(!measured.is_interior(), "{measured:?}");
        // Two balls side by side: the centre between them is not enclosed.
        let mut pair = sphere(Vec3::new(-2.0, 0.0, 0.0), 1.0);
        pair.extend(sphere(Vec3::new(2.0, 0.0, 0.0), 1.0));
        assert!(inside_view(&scene_of("pair", &pair)).is_none());
        // A vessel: outward faces, open at the top.
        let vessel = scene_of("vessel", &box_faces(LO, HI, false, &[Vec3::Y]));
        assert!(inside_view(&vessel).is_none());
        // A floor plane alone.
        let floor = box_faces(LO, Vec3::new(HI.x, LO.y, HI.z), false, &[]);
        assert!(inside_view(&scene_of("floor", &floor)).is_none());
    }

    #[test]
    fn a_shell_open_at_one_side_is_looked_into_from_that_side() {
        // Like the Cornell box: outward faces, the +x side open, a block inside.
        let mut faces = box_faces(LO, HI, false, &[Vec3::X]);
        faces.extend(box_faces(
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
            false,
            &[],
        ));
        let set = scene_of("set", &faces);
        let measured = Enclosure::measure(&set).unwrap();
        assert!(measured.is_interior(), "{measured:?}");
        assert_eq!(measured.open_side, Some(Vec3::X));
        let rig = inside_view(&set).unwrap();
        let pose = crate::scene::camera::OrbitPose::at_frame(&rig, 0);
        let eye = pose.eye();
        assert!(
            (eye.y - 1.5).abs() < 1e-3 && eye.z.abs() < 1e-3,
            "level, on the axis: {eye}"
        );
        assert!((pose.target - eye).normalize().x < -0.99, "looking in");
        // Far enough in front of the opening (4 wide, 3 high) for it to fill the view.
        let half_fov = (rig.fov_y_degrees.to_radians() * 0.5).tan();
        let back = eye.x - HI.x;
        assert!(back * half_fov >= 2.0 && back * half_fov < 2.5, "{back}");
        // A small doorway is no open side: a closed building with a door is an object.
        let mut building = box_faces(LO, HI, false, &[Vec3::X]);
        building.extend(box_faces(
            Vec3::new(HI.x, LO.y, LO.z),
            Vec3::new(HI.x, HI.y, -0.5),
            false,
            &[],
        ));
        building.extend(box_faces(
            Vec3::new(HI.x, LO.y, 0.5),
            Vec3::new(HI.x, HI.y, HI.z),
            false,
            &[],
        ));
        building.extend(box_faces(
            Vec3::new(HI.x, 2.0, -0.5),
            Vec3::new(HI.x, HI.y, 0.5),
            false,
            &[],
        ));
        let measured = Enclosure::measure(&scene_of("building", &building)).unwrap();
        assert_eq!(measured.open_side, None, "{measured:?}");
        assert!(!measured.is_interior());
        // A closed shell open only at the top (a courtyard) looks along its long axis.
        let courtyard = scene_of("courtyard", &box_faces(LO, HI, true, &[Vec3::Y]));
        let pose = crate::scene::camera::OrbitPose::at_frame(&inside_view(&courtyard).unwrap(), 0);
        assert!((pose.target - pose.eye()).normalize().x > 0.99);
    }

    #[test]
    fn a_wall_between_the_centre_and_the_eye_moves_the_eye_in() {
        let mut faces = box_faces(LO, HI, true, &[]);
        // A partition across the room at x = -1.
        faces.extend(box_faces(
            Vec3::new(-1.0, LO.y, LO.z),
            Vec3::new(-1.0, HI.y, HI.z),
            false,
            &[],
        ));
        let pose = crate::scene::camera::OrbitPose::at_frame(
            &inside_view(&scene_of("rooms", &faces)).unwrap(),
            0,
        );
        let eye = pose.eye();
        assert!(
            eye.x > -1.0 && eye.x < 0.0,
            "in front of the partition: {eye}"
        );
    }
}
