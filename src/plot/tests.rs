//! Geometry of the pictures (what is drawn where, with which width and colour), and that the
//! files are PNGs of the promised size. Scenes are built by hand: no physics runs here.

use super::build::{
    FORCE_WIDTH, MAX_SWEEP, Projection, VECTOR_RADII, classify_bonds, format_length, picture,
    round_length,
};
use super::picture::*;
use super::*;
use crate::lang::command::{PlotItem, View, WallGeom};
use crate::sim::Vec3;
use crate::sim::contacts::{BridgeState, ContactState, PairWithState, WallPair};
use crate::sim::scene::Reference;
use crate::sim::scene::Wall;

const R: f64 = 0.01;

/// A non-periodic 1 m cube with particles of radius R at the given centres (ids 1, 2, ...).
fn scene_at(centres: &[[f64; 3]]) -> Scene {
    let mut s = Scene::new([1.0, 1.0, 1.0], 100, 100, 2);
    s.unchecked().settings.periodic = [false; 3];
    for (k, c) in centres.iter().enumerate() {
        s.unchecked().particles.push(
            k as u32 + 1,
            Vec3::from(*c),
            Vec3::zeros(),
            Vec3::zeros(),
            R,
            1.0,
            1,
            1,
            0,
        );
    }
    *s.unchecked().next_id = centres.len() as u32 + 1;
    s
}

/// A chain along x with spacing 2R at height z = 0.5.
fn chain(n: usize) -> Scene {
    let c: Vec<[f64; 3]> = (0..n)
        .map(|k| [0.1 + 2.0 * R * k as f64, 0.5, 0.5])
        .collect();
    scene_at(&c)
}

/// A liquid bridge as the physics makes it (two wet spheres pressed together), so that the
/// tests do not depend on the fields of `BridgeState` beyond the two forces they set.
fn bridge_template() -> Box<BridgeState> {
    let mut session = crate::session::Session::new(Box::new(std::io::sink()), false)
        .with_diagnostics(Box::new(std::io::sink()));
    for l in [
        "start 0.1 0.1 0.1 100 10 2",
        "set open all",
        "rad 0.001 1",
        "density 2500 1",
        "ymd 1e8 1",
        "pra 0.3 1",
        "cr 0.05 0.05 0.05 0.01 0 0 0 0 0 1 1",
        "cr 0.052000000001 0.05 0.05 -0.01 0 0 0 0 0 1 1",
        "liquid 1 0.07 0 0",
        "cycle 2",
    ] {
        if let Err(e) = session.run_line(l) {
            panic!("{l}: {}", e.message);
        }
    }
    let scene = session.scene.expect("scene");
    scene
        .contacts()
        .iter()
        .find_map(|p| p.s.bridge.clone())
        .expect("a bridge between touching wet spheres")
}

/// A contact state: solid (touching, elastic and dashpot force) and optionally a bridge
/// (static attractive, viscous compressive-positive).
fn state(touching: bool, normal: f64, damp: f64, bridge: Option<(f64, f64)>) -> ContactState {
    ContactState {
        touching,
        normal_force: normal,
        damp_force: damp,
        bridge: bridge.map(|(fs, fv)| {
            let mut b = bridge_template();
            b.f_static = fs;
            b.f_visc = fv;
            b
        }),
        ..Default::default()
    }
}

fn pair(s: &Scene, ida: u32, idb: u32, st: ContactState) -> PairWithState {
    let i = s.particles().id.iter().position(|&x| x == ida).expect("id");
    let j = s.particles().id.iter().position(|&x| x == idb).expect("id");
    PairWithState {
        i: i as u32,
        j: j as u32,
        ida,
        idb,
        s: st,
    }
}

fn touching(s: &mut Scene, bonds: &[(u32, u32)]) {
    for &(a, b) in bonds {
        let p = pair(s, a, b, state(true, 1.0, 0.0, None));
        s.unchecked().contacts.push(p);
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

// ---- projection and depth order ---------------------------------------------------------

#[test]
fn projection_of_each_view() {
    let x = Vec3::new(1.0, 2.0, 3.0);
    let xz = Projection::of(View::Xz, false);
    assert_eq!(xz.project(&x), [1.0, 3.0]);
    assert_eq!(xz.depth(&x), 2.0); // looking along +y: larger y is farther
    assert_eq!(xz.axes(), ["x", "z"]);
    let yz = Projection::of(View::Yz, false);
    assert_eq!(yz.project(&x), [2.0, 3.0]);
    assert_eq!(yz.depth(&x), -1.0); // looking along -x
    let xy = Projection::of(View::Xy, false);
    assert_eq!(xy.project(&x), [1.0, 2.0]);
    assert_eq!(xy.depth(&x), -3.0); // from above
    // 2-D mode always draws x-y.
    assert_eq!(Projection::of(View::Xz, true), xy);
    assert_eq!(Projection::of(View::Yz, true), xy);
    // No mirror images: right × up points toward the viewer, and depth decreases that way.
    for p in [xz, yz, xy] {
        let mut e = [Vec3::zeros(), Vec3::zeros()];
        e[0][p.right] = 1.0;
        e[1][p.up] = 1.0;
        assert_eq!(e[0].cross(&e[1]), p.toward());
        assert!(p.depth(&(x + p.toward())) < p.depth(&x));
    }
}

#[test]
fn discs_far_first_in_each_view() {
    // Three particles stacked along y (XZ depth), x (YZ depth) and z (XY depth) at once.
    let mut s = scene_at(&[[0.2, 0.5, 0.7], [0.5, 0.8, 0.2], [0.8, 0.2, 0.5]]);
    let order = |s: &Scene| -> Vec<u32> {
        picture(s, &[PlotItem::Ball])
            .expect("picture")
            .discs
            .iter()
            .map(|d| d.id)
            .collect()
    };
    s.unchecked().settings.view = View::Xz; // far = large y
    assert_eq!(order(&s), vec![2, 1, 3]);
    s.unchecked().settings.view = View::Yz; // far = small x
    assert_eq!(order(&s), vec![1, 2, 3]);
    s.unchecked().settings.view = View::Xy; // far = small z
    assert_eq!(order(&s), vec![2, 3, 1]);
    s.unchecked().settings.two_d = true;
    s.unchecked().settings.view = View::Xz;
    assert_eq!(order(&s), vec![2, 3, 1]);
    let pic = picture(&s, &[PlotItem::Disks]).expect("picture");
    assert!(pic.discs.iter().all(|d| d.shade == Shade::Flat));
    assert_eq!(pic.axes, ["x", "y"]);
    let d = pic.discs.iter().find(|d| d.id == 3).expect("disc 3");
    assert_eq!(d.centre, [0.8, 0.2]);
    assert_eq!(d.radius, R);
    assert_eq!(d.fill, colour::MATERIAL[0]);
}

#[test]
fn bounds_hold_the_particles_and_the_scale_bar_is_round() {
    let s = scene_at(&[[0.2, 0.5, 0.3], [0.6, 0.5, 0.4]]);
    let pic = picture(&s, &[PlotItem::Ball]).expect("picture");
    let b = pic.bounds;
    assert!(b.umin < 0.19 && b.umax > 0.61 && b.vmin < 0.29 && b.vmax > 0.41);
    assert!(
        b.umax < 0.65 && b.vmax < 0.45,
        "tight around the particles: {b:?}"
    );
    let bar = pic.scale_bar.expect("scale bar");
    assert_eq!(bar.length, 0.05);
    assert_eq!(bar.label, "50 mm");
    assert_eq!(round_length(0.37), 0.2);
    assert_eq!(round_length(1.0), 1.0);
    assert_eq!(round_length(0.099), 0.05);
    assert_eq!(round_length(0.0), 0.0);
    assert_eq!(format_length(2e-4), "200 µm");
    assert_eq!(format_length(1.0), "1 m");
    assert_eq!(format_length(5e-9), "5 nm");
}

// ---- force networks ---------------------------------------------------------------------

/// 1-2: solid only (2.0 elastic + 0.5 dashpot); 2-3: bridge only, tensile (static 1.0);
/// 3-4: both (solid 1.0, bridge static 0.3 attractive, viscous 0.1 compressive, i.e.
/// resisting approach: net bridge −0.2); 4-5: a candidate with neither.
fn force_scene() -> Scene {
    let mut s = chain(5);
    let c = vec![
        pair(&s, 1, 2, state(true, 2.0, 0.5, None)),
        pair(&s, 2, 3, state(false, 0.0, 0.0, Some((1.0, 0.0)))),
        pair(&s, 3, 4, state(true, 1.0, 0.0, Some((0.3, 0.1)))),
        pair(&s, 4, 5, state(false, 0.0, 0.0, None)),
    ];
    s.unchecked().contacts.set_pairs(c);
    s
}

fn force_lines(s: &Scene, it: PlotItem) -> Vec<(Tag, f64, f64, Rgb, Mark)> {
    let pic = picture(s, &[it]).expect("picture");
    pic.segments
        .iter()
        .filter(|g| matches!(g.layer, Layer::Force(_)))
        .map(|g| (g.tag, g.value, g.width, g.colour, g.mark))
        .collect()
}

#[test]
fn solid_forces_are_the_touching_contacts() {
    let s = force_scene();
    let l = force_lines(&s, PlotItem::MForces);
    assert_eq!(l.len(), 2, "{l:?}");
    // Widest first, so that thin lines stay visible on top.
    assert_eq!(l[0].0, Tag::Pair(1, 2));
    assert_eq!(l[1].0, Tag::Pair(3, 4));
    assert!(close(l[0].1, 2.5));
    assert!(
        close(l[0].2, FORCE_WIDTH * R),
        "widest = the current maximum"
    );
    assert!(close(l[1].2, 1.0 / 2.5 * FORCE_WIDTH * R));
    assert!(
        l.iter()
            .all(|x| x.3 == colour::COMPRESSIVE && x.4 == Mark::Compressive)
    );
}

#[test]
fn bridge_forces_are_tensile_and_separate() {
    let s = force_scene();
    let l = force_lines(&s, PlotItem::LForces);
    assert_eq!(l.len(), 2, "{l:?}");
    assert_eq!(l[0].0, Tag::Pair(2, 3));
    assert!(close(l[0].1, -1.0));
    assert!(close(l[0].2, FORCE_WIDTH * R));
    assert_eq!(l[1].0, Tag::Pair(3, 4));
    assert!(close(l[1].1, -0.2));
    assert!(close(l[1].2, 0.2 * FORCE_WIDTH * R));
    assert!(
        l.iter()
            .all(|x| x.3 == colour::TENSILE && x.4 == Mark::Tensile)
    );
}

#[test]
fn total_forces_add_solid_and_bridge() {
    let s = force_scene();
    let l = force_lines(&s, PlotItem::Forces);
    assert_eq!(l.len(), 3, "{l:?}");
    let f = |t: Tag| *l.iter().find(|x| x.0 == t).expect("line");
    let (a, b, c) = (f(Tag::Pair(1, 2)), f(Tag::Pair(2, 3)), f(Tag::Pair(3, 4)));
    assert!(close(a.1, 2.5) && a.3 == colour::COMPRESSIVE);
    assert!(close(b.1, -1.0) && b.3 == colour::TENSILE);
    assert!(close(c.1, 0.8) && c.3 == colour::COMPRESSIVE);
    assert!(close(b.2, 1.0 / 2.5 * FORCE_WIDTH * R));
    // The line joins the two centres in view coordinates.
    let pic = picture(&s, &[PlotItem::Forces]).expect("picture");
    let g = pic
        .segments
        .iter()
        .find(|g| g.tag == Tag::Pair(1, 2))
        .expect("1-2");
    assert_eq!(g.a, [0.1, 0.5]);
    assert!(close(g.b[0], 0.1 + 2.0 * R) && g.b[1] == 0.5);
}

#[test]
fn overlaid_force_sets_share_one_scale() {
    let s = force_scene();
    let pic = picture(&s, &[PlotItem::LForces, PlotItem::MForces]).expect("picture");
    let l: Vec<(Layer, Tag, f64)> = pic
        .segments
        .iter()
        .map(|g| (g.layer, g.tag, g.width / (FORCE_WIDTH * R)))
        .collect();
    let solid = Layer::Force(ForceSet::Solid);
    let bridge = Layer::Force(ForceSet::Bridge);
    // Widest first across both sets; ties keep the order of the items.
    let want = [
        (solid, Tag::Pair(1, 2), 1.0),
        (bridge, Tag::Pair(2, 3), 0.4),
        (solid, Tag::Pair(3, 4), 0.4),
        (bridge, Tag::Pair(3, 4), 0.08),
    ];
    assert_eq!(l.len(), want.len(), "{l:?}");
    for (got, want) in l.iter().zip(want.iter()) {
        assert_eq!((got.0, got.1), (want.0, want.1), "{l:?}");
        assert!(close(got.2, want.2), "{l:?}");
    }
    let headers: Vec<&str> = pic
        .legend
        .iter()
        .filter(|e| e.swatch == Swatch::None)
        .map(|e| e.text.as_str())
        .collect();
    assert_eq!(
        headers,
        vec![
            "liquid-bridge forces (LFOrces)",
            "solid contact forces (MFOrces)"
        ]
    );
}

#[test]
fn wall_contacts_end_on_the_wall() {
    let mut s = scene_at(&[[0.3, 0.5, 0.1 + 0.9 * R]]);
    s.unchecked().walls.push(Wall {
        geom: WallGeom::Plane {
            normal: [0.0, 0.0, 1.0],
            d: 0.1,
        },
        vel: [0.0; 3],
        vr: 0.0,
        material: 1,
        servo: None,
        force: [0.0; 3],
        normal_force: 0.0,
        disp: [0.0; 3],
        travel: 0.0,
    });
    s.unchecked().contacts.wall_pairs_mut().push(WallPair {
        i: 0,
        id: 1,
        wall: 0,
        s: state(true, 3.0, 0.0, None),
    });
    let pic = picture(&s, &[PlotItem::Forces, PlotItem::Wall]).expect("picture");
    let g = pic
        .segments
        .iter()
        .find(|g| g.tag == Tag::WallContact(1, 0))
        .expect("wall contact line");
    assert_eq!(g.a, [0.3, 0.1 + 0.9 * R]);
    assert!(close(g.b[0], 0.3) && close(g.b[1], 0.1));
    assert_eq!(g.colour, colour::COMPRESSIVE);
    // The wall itself: a horizontal line at z = 0.1 across the picture, hatched below.
    let w: Vec<&Segment> = pic
        .segments
        .iter()
        .filter(|g| g.layer == Layer::Wall && g.mark == Mark::Plain)
        .collect();
    assert_eq!(w.len(), 1);
    assert!(close(w[0].a[1], 0.1) && close(w[0].b[1], 0.1));
    assert!(close(w[0].a[0].min(w[0].b[0]), pic.bounds.umin));
    assert!(close(w[0].a[0].max(w[0].b[0]), pic.bounds.umax));
    let hatch = pic.segments.iter().filter(|g| g.mark == Mark::Hatch);
    assert!(hatch.clone().count() > 5);
    assert!(hatch.into_iter().all(|g| g.b[1] < 0.1));
    // Seen from above the plane is parallel to the view: not drawn, said so.
    s.unchecked().settings.view = View::Xy;
    let pic = picture(&s, &[PlotItem::Wall]).expect("picture");
    assert!(pic.segments.is_empty());
    assert!(pic.notes.iter().any(|n| n.contains("parallel")));
}

#[test]
fn walls_out_of_the_picture_extend_it_and_spheres_are_rings() {
    let mut s = scene_at(&[[0.5, 0.5, 0.5]]);
    let wall = |geom| Wall {
        geom,
        vel: [0.0; 3],
        vr: 0.0,
        material: 1,
        servo: None,
        force: [0.0; 3],
        normal_force: 0.0,
        disp: [0.0; 3],
        travel: 0.0,
    };
    s.unchecked().walls.push(wall(WallGeom::Plane {
        normal: [1.0, 0.0, 0.0],
        d: 0.2,
    }));
    s.unchecked().walls.push(wall(WallGeom::Obstacle {
        centre: [0.5, 0.9, 0.7],
        radius: 0.1,
    }));
    let pic = picture(&s, &[PlotItem::Wall]).expect("picture");
    let line = pic
        .segments
        .iter()
        .find(|g| g.tag == Tag::Wall(0) && g.mark == Mark::Plain)
        .expect("plane x = 0.2");
    assert!(close(line.a[0], 0.2) && close(line.b[0], 0.2));
    assert!(pic.bounds.umin < 0.2);
    assert_eq!(pic.rings.len(), 1);
    assert_eq!(pic.rings[0].centre, [0.5, 0.7]);
    assert_eq!(pic.rings[0].radius, 0.1);
    assert!(pic.rings[0].fill.is_some(), "obstacles are shaded");
    assert!(pic.bounds.vmax > 0.8);
    // A die along z, seen from the side (XZ): its two sides x = 0.5 ± 0.3, the particles
    // between them; from the top (XY) a circle.
    s.unchecked().walls.clear();
    s.unchecked().walls.push(wall(WallGeom::Cylinder {
        point: [0.5, 0.5, 0.0],
        axis: [0.0, 0.0, 1.0],
        radius: 0.3,
    }));
    let pic = picture(&s, &[PlotItem::Wall]).expect("picture");
    let sides: Vec<f64> = pic
        .segments
        .iter()
        .filter(|g| g.tag == Tag::Wall(0) && g.mark == Mark::Plain)
        .map(|g| g.a[0])
        .collect();
    assert_eq!(sides.len(), 2, "{sides:?}");
    assert!(sides.iter().any(|&u| close(u, 0.2)) && sides.iter().any(|&u| close(u, 0.8)));
    s.unchecked().settings.view = View::Xy;
    let pic = picture(&s, &[PlotItem::Wall]).expect("picture");
    assert_eq!(pic.rings.len(), 1);
    assert_eq!(
        (pic.rings[0].centre, pic.rings[0].radius),
        ([0.5, 0.5], 0.3)
    );
}

#[test]
fn periodic_pairs_are_drawn_as_two_halves() {
    let mut s = scene_at(&[[0.005, 0.5, 0.5], [0.995, 0.5, 0.5]]);
    s.unchecked().settings.periodic = [true; 3];
    let p = pair(&s, 1, 2, state(true, 1.0, 0.0, None));
    s.unchecked().contacts.push(p);
    let pic = picture(&s, &[PlotItem::MForces]).expect("picture");
    assert_eq!(pic.segments.len(), 2);
    assert_eq!(pic.segments[0].a, [0.005, 0.5]);
    assert!(close(pic.segments[0].b[0], 0.0));
    assert_eq!(pic.segments[1].a, [0.995, 0.5]);
    assert!(close(pic.segments[1].b[0], 1.0));
}

// ---- clusters ---------------------------------------------------------------------------

fn fills(pic: &Picture) -> Vec<(u32, Rgb)> {
    let mut v: Vec<(u32, Rgb)> = pic.discs.iter().map(|d| (d.id, d.fill)).collect();
    v.sort_by_key(|x| x.0);
    v
}

#[test]
fn a_chain_that_breaks_in_two() {
    // 13 particles in a chain; the bond 11-12 is gone: 11 particles (black) and 2 (cyan).
    let mut s = chain(13);
    let bonds: Vec<(u32, u32)> = (1..13).filter(|&k| k != 11).map(|k| (k, k + 1)).collect();
    touching(&mut s, &bonds);
    let pic = picture(&s, &[PlotItem::Cluster]).expect("picture");
    let f = fills(&pic);
    assert_eq!(f.len(), 13);
    for (id, c) in f {
        let want = if id <= 11 {
            colour::CLUSTER[2]
        } else {
            colour::CLUSTER[1]
        };
        assert_eq!(c, want, "particle {id}");
    }
    assert!(pic.legend.iter().any(|e| e.text == "11-50: 1, 11"));
    assert!(pic.legend.iter().any(|e| e.text == "2-10: 1, 2"));
    // Whole again: one cluster of 13 (black).
    let mut s = chain(13);
    let bonds: Vec<(u32, u32)> = (1..13).map(|k| (k, k + 1)).collect();
    touching(&mut s, &bonds);
    let pic = picture(&s, &[PlotItem::Cluster]).expect("picture");
    assert!(fills(&pic).iter().all(|x| x.1 == colour::CLUSTER[2]));
}

#[test]
fn a_cluster_of_three_bridges() {
    // 1-2-3 joined by three bridges (a triangle), 4 touches 3 without a bridge, 5 alone.
    let mut s = scene_at(&[
        [0.5, 0.5, 0.5],
        [0.5 + 2.0 * R, 0.5, 0.5],
        [0.5 + R, 0.5, 0.5 + 1.7320508 * R],
        [0.5 + R, 0.5, 0.5 + 3.7320508 * R],
        [0.8, 0.5, 0.8],
    ]);
    let wet = |s: &Scene, a, b| pair(s, a, b, state(true, 0.5, 0.0, Some((0.2, 0.0))));
    let c = vec![
        wet(&s, 1, 2),
        wet(&s, 1, 3),
        wet(&s, 2, 3),
        pair(&s, 3, 4, state(true, 0.5, 0.0, None)),
    ];
    s.unchecked().contacts.set_pairs(c);
    let pic = picture(&s, &[PlotItem::LCluster]).expect("picture");
    let want = [
        colour::CLUSTER[1],
        colour::CLUSTER[1],
        colour::CLUSTER[1],
        colour::CLUSTER[0],
        colour::CLUSTER[0],
    ];
    let got: Vec<Rgb> = fills(&pic).into_iter().map(|x| x.1).collect();
    assert_eq!(got, want);
    // By solid contacts 4 joins them: a cluster of 4 and a singlet.
    let pic = picture(&s, &[PlotItem::Cluster, PlotItem::Disks]).expect("picture");
    let got: Vec<Rgb> = fills(&pic).into_iter().map(|x| x.1).collect();
    assert_eq!(got[3], colour::CLUSTER[1]);
    assert_eq!(got[4], colour::CLUSTER[0]);
    assert!(pic.discs.iter().all(|d| d.shade == Shade::Flat));
}

#[test]
fn cluster_labels_per_particle() {
    // Chain 1-2-3 | 4-5 and a singlet 6 (ids in any order); a bond to an unknown id is ignored.
    let ids = [5, 1, 6, 2, 4, 3];
    let labels = crate::analysis::cluster_labels(&ids, &[(1, 2), (2, 3), (4, 5), (5, 99)]);
    assert_eq!(labels, vec![0, 1, 2, 1, 0, 1]);
    assert!(crate::analysis::cluster_labels(&[], &[(1, 2)]).is_empty());
}

#[test]
fn cluster_classes_follow_the_thesis() {
    let c: Vec<usize> = [1, 2, 10, 11, 50, 51, 200, 201, 600, 601, 5000]
        .iter()
        .map(|&n| cluster_class(n))
        .collect();
    assert_eq!(c, vec![0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5]);
    assert_eq!(colour::CLUSTER[0], Rgb(0, 170, 0)); // green singlets
    assert_eq!(colour::CLUSTER[5], Rgb(220, 0, 0)); // red > 600
}

// ---- reference-based items --------------------------------------------------------------

#[test]
fn cnd_kept_new_broken() {
    assert_eq!(
        classify_bonds(&[(1, 2), (2, 3), (3, 4)], &[(1, 2), (3, 4), (4, 5)]),
        vec![
            ((1, 2), Mark::Kept),
            ((2, 3), Mark::Broken),
            ((3, 4), Mark::Kept),
            ((4, 5), Mark::New)
        ]
    );
    assert_eq!(classify_bonds(&[], &[]), vec![]);
    assert_eq!(classify_bonds(&[(1, 9)], &[]), vec![((1, 9), Mark::Broken)]);

    // (Spheres 1e-3 R apart: only the states given touch, `Scene::touching_pairs`.)
    let c: Vec<[f64; 3]> = (0..5)
        .map(|k| [0.1 + 2.001 * R * k as f64, 0.5, 0.5])
        .collect();
    let mut s = scene_at(&c);
    touching(&mut s, &[(1, 2), (2, 3), (3, 4)]);
    // A bridge 4-5 in the reference.
    let p = pair(&s, 4, 5, state(false, 0.0, 0.0, Some((0.1, 0.0))));
    s.unchecked().contacts.push(p);
    *s.unchecked().reference = Some(Reference::take(&s));
    s.unchecked().contacts.clear_pairs();
    touching(&mut s, &[(1, 2), (3, 4), (4, 5)]);
    let pic = picture(&s, &[PlotItem::Cnd]).expect("picture");
    let mut l: Vec<(Tag, Mark, Rgb)> = pic
        .segments
        .iter()
        .map(|g| (g.tag, g.mark, g.colour))
        .collect();
    // Drawn broken first, then kept, then new.
    assert_eq!(
        l,
        vec![
            (Tag::Pair(2, 3), Mark::Broken, colour::BROKEN),
            (Tag::Pair(1, 2), Mark::Kept, colour::KEPT),
            (Tag::Pair(3, 4), Mark::Kept, colour::KEPT),
            (Tag::Pair(4, 5), Mark::New, colour::NEW),
        ]
    );
    assert!(pic.legend.iter().any(|e| e.text == "broken: 1"));
    // LCNd: the bridge 4-5 is gone.
    l = picture(&s, &[PlotItem::LCnd])
        .expect("picture")
        .segments
        .iter()
        .map(|g| (g.tag, g.mark, g.colour))
        .collect();
    assert_eq!(l, vec![(Tag::Pair(4, 5), Mark::Broken, colour::BROKEN)]);
    // A particle that left: its broken bond is not drawn, and said so.
    s.unchecked().particles.remove(0);
    let pic = picture(&s, &[PlotItem::Cnd]).expect("picture");
    assert!(pic.segments.iter().all(|g| g.tag != Tag::Pair(1, 2)));
    assert!(pic.notes.iter().any(|n| n.contains("no longer present")));
}

#[test]
fn displacement_and_rotation_since_the_reference() {
    let mut s = chain(3);
    *s.unchecked().reference = Some(Reference::take(&s));
    s.unchecked().particles.pos[0] += Vec3::new(0.002, 0.5, 0.0); // the y part is not seen in XZ
    s.unchecked().particles.pos[1] += Vec3::new(0.0, 0.0, -0.001);
    s.unchecked().particles.rot[0] = Vec3::new(0.0, -0.2, 0.0); // −y points at the viewer: anticlockwise
    s.unchecked().particles.rot[1] = Vec3::new(0.0, 0.1, 0.0);
    s.unchecked().particles.rot[2] = Vec3::new(0.3, 0.0, 0.3); // nothing about the viewing axis
    let pic = picture(&s, &[PlotItem::RDisp, PlotItem::Rotation]).expect("picture");
    assert_eq!(pic.arrows.len(), 2);
    let a = &pic.arrows[0];
    assert_eq!((a.id, a.kind), (1, VectorKind::Displacement));
    assert!(close(a.value, 0.002));
    assert!(close(a.to[0] - a.from[0], VECTOR_RADII * R) && close(a.to[1], a.from[1]));
    let b = &pic.arrows[1];
    assert!(close(b.to[1] - b.from[1], -0.5 * VECTOR_RADII * R));
    assert_eq!(pic.arcs.len(), 2);
    assert!(close(pic.arcs[0].sweep, MAX_SWEEP));
    assert_eq!(pic.arcs[0].colour, colour::ANTICLOCKWISE);
    assert!(close(pic.arcs[1].sweep, -0.5 * MAX_SWEEP));
    assert_eq!(pic.arcs[1].colour, colour::CLOCKWISE);
    // Arcs carry their particle's depth: the renderer draws each with its disc.
    let xz = Projection::of(View::Xz, false);
    assert_eq!(pic.arcs[0].depth, xz.depth(&s.particles().pos[0]));
    // Periodic: a particle that crossed the side moved a little, not the cell length.
    let mut s = scene_at(&[[0.999, 0.5, 0.5]]);
    s.unchecked().settings.periodic = [true; 3];
    *s.unchecked().reference = Some(Reference::take(&s));
    s.unchecked().particles.pos[0].x = 0.001;
    let pic = picture(&s, &[PlotItem::RDisp]).expect("picture");
    assert!(close(pic.arrows[0].value, 0.002));
    // A particle created after the reference has no displacement.
    let mut s = chain(2);
    *s.unchecked().reference = Some(Reference::take(&s));
    s.unchecked().particles.push(
        9,
        Vec3::new(0.9, 0.5, 0.5),
        Vec3::zeros(),
        Vec3::zeros(),
        R,
        1.0,
        1,
        1,
        0,
    );
    s.unchecked().particles.pos[0].x += 0.001;
    let pic = picture(&s, &[PlotItem::RDisp]).expect("picture");
    assert_eq!(pic.arrows.len(), 1);
    assert!(
        pic.notes
            .iter()
            .any(|n| n.contains("1 particles created after"))
    );
}

#[test]
fn velocity_vectors_and_couples() {
    let mut s = chain(3);
    s.unchecked().particles.vel[0] = Vec3::new(0.0, 0.0, -2.0);
    s.unchecked().particles.vel[1] = Vec3::new(1.0, 0.0, 0.0);
    s.unchecked().particles.moment[2] = Vec3::new(0.0, 5.0, 0.0); // +y: clockwise in the XZ view
    let pic = picture(&s, &[PlotItem::Velocity, PlotItem::Couple]).expect("picture");
    assert_eq!(pic.arrows.len(), 2);
    assert!(close(
        pic.arrows[0].to[1] - pic.arrows[0].from[1],
        -VECTOR_RADII * R
    ));
    assert!(close(
        pic.arrows[1].to[0] - pic.arrows[1].from[0],
        0.5 * VECTOR_RADII * R
    ));
    assert_eq!(pic.arcs.len(), 1);
    assert_eq!(pic.arcs[0].kind, ArcKind::Couple);
    assert!(close(pic.arcs[0].sweep, -MAX_SWEEP));
    // At rest: no vectors, and a note.
    let s = chain(2);
    let pic = picture(&s, &[PlotItem::Velocity]).expect("picture");
    assert!(pic.arrows.is_empty());
    assert!(pic.notes.iter().any(|n| n.contains("zero")));
}

// ---- bad input --------------------------------------------------------------------------

#[test]
fn items_that_need_a_reference_say_so() {
    let s = chain(2);
    for it in [
        PlotItem::RDisp,
        PlotItem::Rotation,
        PlotItem::Cnd,
        PlotItem::LCnd,
    ] {
        let e = png_bytes(&s, &[PlotItem::Bou, it]).expect_err("needs a reference");
        assert!(e.contains("PLot SAVe"), "{e}");
        assert!(e.contains(&build::item_name(it).to_uppercase()), "{e}");
    }
    let e = png_bytes(&s, &[PlotItem::Cluster, PlotItem::LCluster]).expect_err("both");
    assert!(e.contains("one of them"), "{e}");
    let e = png_bytes(&s, &[PlotItem::History, PlotItem::Bou]).expect_err("history alone");
    assert!(e.contains("alone"), "{e}");
    let e = png_bytes(&s, &[PlotItem::History]).expect_err("nothing recorded");
    assert!(e.contains("SET HIStory"), "{e}");
    let e = png_bytes(&s, &[PlotItem::Save]).expect_err("nothing to draw");
    assert!(e.contains("at least one item"), "{e}");
}

#[test]
fn an_empty_scene_draws_the_boundary_and_says_so() {
    let s = scene_at(&[]);
    let pic = picture(&s, &[PlotItem::Ball, PlotItem::Bou]).expect("picture");
    assert!(pic.discs.is_empty());
    assert!(pic.notes.iter().any(|n| n.contains("no particles")));
    assert_eq!(
        pic.segments
            .iter()
            .filter(|g| g.layer == Layer::Boundary)
            .count(),
        4
    );
    assert!(pic.bounds.umin < 0.0 && pic.bounds.umax > 1.0);
    let pic = picture(&s, &[PlotItem::Forces]).expect("picture");
    assert!(pic.bounds.width() > 0.0 && pic.bounds.height() > 0.0);
    assert!(png_bytes(&s, &[PlotItem::Forces, PlotItem::Velocity]).is_ok());
}

#[test]
fn boundary_marks_periodic_sides_dashed() {
    let mut s = chain(2);
    s.unchecked().settings.periodic = [true, false, false];
    let pic = picture(&s, &[PlotItem::Bou, PlotItem::Grid]).expect("picture");
    let b: Vec<&Segment> = pic
        .segments
        .iter()
        .filter(|g| g.layer == Layer::Boundary)
        .collect();
    assert_eq!(b.len(), 4, "BOU and GRId draw the outline once");
    for g in b {
        let vertical = g.a[0] == g.b[0];
        assert_eq!(g.mark == Mark::Dashed, vertical, "{g:?}");
    }
}

// ---- files ------------------------------------------------------------------------------

/// Checks the PNG signature and returns (width, height) from the IHDR chunk.
pub(crate) fn png_size(b: &[u8]) -> (u32, u32) {
    assert!(b.len() > 33, "too short for a PNG");
    assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&b[12..16], b"IHDR", "first chunk is IHDR");
    let be = |k: usize| u32::from_be_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
    (be(16), be(20))
}

#[test]
fn file_names_are_predictable() {
    assert_eq!(
        file_name(200, &[PlotItem::Bou, PlotItem::RDisp]),
        "plot_c00000200_bou_rdisp.png"
    );
    assert_eq!(
        file_name(
            123456789,
            &[
                PlotItem::Save,
                PlotItem::LCnd,
                PlotItem::Ball,
                PlotItem::LCnd
            ]
        ),
        "plot_c123456789_lcnd_ball.png"
    );
}

#[test]
fn pictures_and_charts_are_wide_pngs() {
    let mut s = force_scene();
    *s.unchecked().reference = Some(Reference::take(&s));
    s.unchecked().particles.vel[0] = Vec3::new(1.0, 0.0, 0.0);
    s.unchecked().particles.moment[1] = Vec3::new(0.0, 1.0, 0.0);
    let all = [
        PlotItem::Ball,
        PlotItem::Bou,
        PlotItem::Forces,
        PlotItem::Cnd,
        PlotItem::Velocity,
        PlotItem::RDisp,
        PlotItem::Rotation,
        PlotItem::Couple,
        PlotItem::Wall,
        PlotItem::Cluster,
    ];
    let (w, h) = png_size(&png_bytes(&s, &all).expect("png"));
    assert!(w >= 1000 && h >= 500, "{w} x {h}");
    for view in [View::Xz, View::Yz, View::Xy] {
        s.unchecked().settings.view = view;
        let (w, _) = png_size(&png_bytes(&s, &[PlotItem::Disks]).expect("png"));
        assert!(w >= 1000);
    }
    for k in 0..5 {
        *s.unchecked().cycle = 10 * k;
        crate::sim::cycle::record_history(&mut s);
    }
    let (w, h) = png_size(&png_bytes(&s, &[PlotItem::History]).expect("chart"));
    assert!(w >= 1000 && h >= 600, "{w} x {h}");
    // One record only still draws.
    s.unchecked().history.rows.truncate(1);
    assert!(png_bytes(&s, &[PlotItem::History]).is_ok());
}

#[test]
fn files_go_to_the_output_directory() {
    let dir = std::env::temp_dir().join(format!("trubal-plot-unit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut s = chain(3);
    *s.unchecked().cycle = 42;
    s.unchecked().settings.out_dir = dir.join("a/b").display().to_string();
    let name = plot(&s, &[PlotItem::Ball, PlotItem::Bou]).expect("written");
    assert!(name.ends_with("plot_c00000042_ball_bou.png"), "{name}");
    let bytes = std::fs::read(&name).expect("file");
    assert!(png_size(&bytes).0 >= 1000);
    // An output "directory" that is a file: a clear error, no panic.
    let file = dir.join("not-a-dir");
    std::fs::write(&file, b"x").expect("write");
    s.unchecked().settings.out_dir = file.join("sub").display().to_string();
    let e = plot(&s, &[PlotItem::Ball]).expect_err("unwritable");
    assert!(e.contains("cannot create the output directory"), "{e}");
    s.unchecked().settings.out_dir = file.display().to_string();
    let e = plot(&s, &[PlotItem::Ball]).expect_err("unwritable");
    assert!(
        e.contains("output directory") || e.contains("cannot write"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
