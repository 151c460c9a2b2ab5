//! Robots in the replay: every link of every robot is a body of the page.
//!
//! - **What a link is drawn as.** Its URDF geometry when it has some that can be drawn
//!   ([`link_geometry`](super::link_geometry)): its `<visual>` elements if all can be drawn, else its
//!   `<collision>` elements, each at its `<origin>` in the link frame. Otherwise, from its mass: a
//!   link with mass is drawn as its inertia-equivalent box ([`derived::inertia_equivalent_box`], as a
//!   shapeless free body): the uniform box with the link's own mass and principal moments
//!   ([`Frame::inertia`], the link as the URDF gave it, before fixed joints merge it into a body),
//!   centred on the link's centre of mass and turned to its principal axes. A link without mass (a
//!   tool or sensor frame such as the double pendulum's `tip`, or a massless root) is drawn as a
//!   small sphere at its frame's origin, of the radius [`marker_radius`]: so are a point mass and an
//!   inertia that is not one (no box matches it). The body's `drawn` field says which:
//!   `"visual"`, `"collision"`, `"inertia_box"` or `"marker"`.
//! - **Where.** A moving link's trajectory row holds the pose of its link frame (origin and
//!   `world_from_link`), not of its centre of mass: the page places the body at that pose and the
//!   parts within it (the part's `position`, link frame). The links fixed to the world (a fixed base
//!   and what is welded to it) have no row: they are fixed bodies of the page, at their place in the
//!   world.
//! - **Colours.** A robot takes one colour of the palette; its moving links are shades of it in turn,
//!   its fixed links a darker shade, its markers a lighter one.

use super::link_geometry::{self, mesh_budget, LinkDrawing, LinkGeometries};
use super::{json_string, numbers};
use tumble::math::{quat_to_wxyz, DMat3, DQuat, DVec3};
use tumble::multibody::model::GeometryRole;
use tumble::multibody::{Frame, RigidInertia};
use tumble::trajectory::derived;
use tumble::world::Robot;
use tumble::MassProperties;

/// Shades of a robot's colour for its moving links, in turn (neighbours differ).
const LINK_SHADES: [f32; 4] = [1.0, 0.72, 0.88, 0.6];
/// Shade of the links fixed to the world.
const FIXED_SHADE: f32 = 0.45;
/// How far a marker's colour is taken towards white.
const MARKER_LIGHTEN: f32 = 0.55;
/// A marker's radius when no link of the robot has a box (m).
const DEFAULT_MARKER_RADIUS: f64 = 0.02;

/// How a link is drawn, in its link frame.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Drawn {
    /// The inertia-equivalent box: half extents (m) along its axes, its centre (the centre of mass)
    /// and `link_from_box`.
    Box { half_extents: DVec3, center: DVec3, link_from_box: DQuat },
    /// A sphere at the frame's origin.
    Marker,
}

/// How a link of inertia `inertia` (its own, in the link frame) is drawn.
fn drawn(inertia: &RigidInertia) -> Drawn {
    if !(inertia.mass > 0.0 && inertia.mass.is_finite()) {
        return Drawn::Marker;
    }
    let c = inertia.com();
    // Ī_c = Ī_o − m (|c|² 1 − c cᵀ) (parallel-axis theorem)
    let c_ct = DMat3::from_cols(c * c.x, c * c.y, c * c.z);
    let inertia_com = inertia.i_o - inertia.mass * (DMat3::from_diagonal(DVec3::splat(c.length_squared())) - c_ct);
    match MassProperties::from_tensor(inertia.mass, inertia_com) {
        Ok(mass) => {
            let (half_extents, link_from_box) = derived::inertia_equivalent_box(&mass);
            Drawn::Box { half_extents, center: c, link_from_box }
        }
        // a point mass, or moments that no body has: nothing to size a box by
        Err(_) => Drawn::Marker,
    }
}

/// The radius of a robot's markers (m): the median over its boxes of their smallest half extent, so
/// that a marker is about as thick as the robot's links; [`DEFAULT_MARKER_RADIUS`] without a box.
fn marker_radius(links: &[Drawn]) -> f64 {
    let mut sizes: Vec<f64> = links
        .iter()
        .filter_map(|d| match d {
            Drawn::Box { half_extents, .. } => Some(half_extents.min_element()),
            Drawn::Marker => None,
        })
        .collect();
    if sizes.is_empty() {
        return DEFAULT_MARKER_RADIUS;
    }
    sizes.sort_by(f64::total_cmp);
    sizes[sizes.len() / 2]
}

/// Appends the page's body entries for the links of `robot` to `out` (JSON objects, each preceded
/// by a comma unless `*first`), in the colour `color`: its moving links first, in the order of its
/// trajectory rows (`index` their place in `trajectory_bodies`), then its links fixed to the world.
/// Returns the warning naming the meshes that could not be read, if any.
pub(super) fn push_bodies(
    out: &mut String,
    first: &mut bool,
    robot: &Robot,
    color: [f32; 3],
    trajectory_bodies: &[String],
) -> Option<String> {
    let moving = (0..robot.link_names().len()).map(|k| robot.link_frame(k));
    let fixed = robot.model.frames.iter().filter(|f| f.body.is_none());
    let frames: Vec<&Frame> = moving.chain(fixed).collect();
    // what each link is drawn as from its mass (the markers sized by the boxes), and from its URDF
    // geometry if it has some that can be drawn (which then wins)
    let from_mass: Vec<Drawn> = frames.iter().map(|f| drawn(&f.inertia)).collect();
    let radius = marker_radius(&from_mass);
    let mut geometries = LinkGeometries::default();
    let from_urdf: Vec<Option<LinkDrawing>> =
        frames.iter().map(|f| geometries.drawing(&robot.model, &f.name)).collect();
    let budget = mesh_budget(from_urdf.iter().flatten());
    for (k, ((frame, from_mass), from_urdf)) in frames.iter().zip(&from_mass).zip(&from_urdf).enumerate() {
        let is_moving = frame.body.is_some();
        let name = format!("{}/{}", robot.name, frame.name);
        let index = if is_moving { trajectory_bodies.iter().position(|n| n == &name) } else { None };
        // the link frame's pose now: for a moving link, that of its row; for a fixed one, its place
        let (position, orientation) = if is_moving {
            let state = robot.link_state(k);
            (state.position, state.orientation)
        } else {
            let world_from_frame = frame.x_from_body.rotation_a_from_b();
            (frame.x_from_body.r, DQuat::from_mat3(&world_from_frame).normalize())
        };
        let shade = if is_moving { LINK_SHADES[k % LINK_SHADES.len()] } else { FIXED_SHADE };
        let mut rgb = color.map(|c| c * shade);
        let (parts, what) = match (from_urdf, *from_mass) {
            (Some(urdf), _) => (
                urdf.parts_json(budget),
                match urdf.role {
                    GeometryRole::Visual => "visual",
                    GeometryRole::Collision => "collision",
                },
            ),
            (None, Drawn::Box { half_extents, center, link_from_box }) => (
                format!(
                    "{{\"geometry\":{{\"type\":\"box\",\"half_extents\":{}}},\"position\":{},\"orientation\":{}}}",
                    numbers(&half_extents.to_array()),
                    numbers(&center.to_array()),
                    numbers(&quat_to_wxyz(link_from_box))
                ),
                "inertia_box",
            ),
            (None, Drawn::Marker) => {
                rgb = rgb.map(|c| c + (1.0 - c) * MARKER_LIGHTEN);
                (
                    format!(
                        "{{\"geometry\":{{\"type\":\"sphere\",\"radius\":{}}},\"position\":[0,0,0],\"orientation\":[1,0,0,0]}}",
                        super::num(radius)
                    ),
                    "marker",
                )
            }
        };
        if !*first {
            out.push(',');
        }
        *first = false;
        use std::fmt::Write as _;
        let _ = write!(
            out,
            "{{\"name\":{},\"robot\":{},\"color\":{},\"index\":{},\"position\":{},\"orientation\":{},\
             \"drawn\":\"{what}\",\"inertia_box\":{},\"marker\":{},\"parts\":[{parts}]}}",
            json_string(&name),
            json_string(&robot.name),
            numbers(&rgb.map(f64::from)),
            index.map_or("null".into(), |i| i.to_string()),
            numbers(&position.to_array()),
            numbers(&quat_to_wxyz(orientation)),
            what == "inertia_box",
            what == "marker",
        );
    }
    link_geometry::warning(&robot.name, &geometries.unreadable)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_link_with_mass_is_its_inertia_box_at_its_centre_of_mass() {
        // a 1 kg rod along z, 1 m long, centre of mass 0.5 m below the link origin
        let rod = RigidInertia::from_com(
            1.0,
            DVec3::new(0.0, 0.0, -0.5),
            DMat3::from_diagonal(DVec3::new(1.0 / 12.0, 1.0 / 12.0, 0.001)),
        );
        let Drawn::Box { half_extents, center, link_from_box } = drawn(&rod) else { panic!("a box") };
        assert!((center - DVec3::new(0.0, 0.0, -0.5)).length() < 1e-15);
        // h_z² = 3 (1/12 + 1/12 − 0.001) / 2, h_x² = h_y² = 3 · 0.001 / 2
        let h_long = (1.5 * (1.0 / 6.0 - 0.001_f64)).sqrt();
        let h_thin = 0.0015_f64.sqrt();
        let along_z = link_from_box * DVec3::new(half_extents.x, half_extents.y, half_extents.z);
        assert!((along_z.z.abs() - h_long).abs() < 1e-9, "{half_extents} {link_from_box}");
        assert!((half_extents.min_element() - h_thin).abs() < 1e-9);
    }

    #[test]
    fn a_massless_link_or_a_point_mass_is_a_marker() {
        assert_eq!(drawn(&RigidInertia::ZERO), Drawn::Marker);
        let point = RigidInertia::from_com(2.0, DVec3::X, DMat3::ZERO);
        assert_eq!(drawn(&point), Drawn::Marker);
        assert_eq!(marker_radius(&[Drawn::Marker]), DEFAULT_MARKER_RADIUS);
    }
}
