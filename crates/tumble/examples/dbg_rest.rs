use tumble::body::{Material, Shape};
use tumble::math::DVec3;
use tumble::{MassProperties, RigidBody, World, WorldConfig};
fn main() {
    let shape = Shape::Box { half_extents: DVec3::new(0.2, 0.2, 0.1) };
    let (m1, i1) = shape.mass_properties(1.0).unwrap();
    let mut b = RigidBody::new("b", MassProperties::from_principal(2.0, i1 * (2.0 / m1)).unwrap());
    b.shape = Some(shape);
    b.state.position = DVec3::new(0.0, 0.0, 0.1);
    b.state.velocity = DVec3::new(3.0, 0.0, 0.0);
    b.material = Material { friction: Some(0.4), restitution: Some(0.0) };
    let mut g = RigidBody::new("g", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
    g.fixed = true;
    g.shape = Some(Shape::Plane);
    let mut w = World::new(WorldConfig { dt: 1e-3, ..WorldConfig::default() }, vec![g, b]);
    for i in 0..1200 {
        w.step().unwrap();
        let s = w.bodies[1].state;
        if i % 200 == 0 || i > 1197 {
            println!("{i} z {:.9} v {:?} w {:?}", s.position.z, s.velocity, s.omega_body);
        }
    }
}
