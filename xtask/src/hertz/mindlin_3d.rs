//! The section in space of `cargo xtask hertz`: Cattaneo-Mindlin in 3D (Johnson, Contact
//! Mechanics, 7.2). Two flat blocks of the same material with the initial gap of two spheres,
//! `g0 = r^2 / (2 R)` (Hertz's half-space geometry, as the section in the plane uses flat
//! blocks with a parabolic gap), the upper block's top a rigid plate pushed with `P` and
//! sheared with `Q < F P` along x, Coulomb friction: the stick disc of radius
//! `c = a (1 - Q/(F P))^(1/3)` (`vem_verify::exact::HertzSphere::stick_radius`), the load
//! carried, and the refusal beyond the capacity. Writes `mindlin-3d.md` and `mindlin-3d.json`
//! (`docs/hertz.md`, section 5).
//!
//! For elastically similar bodies the pressure does not depend on the shear and pushing leaves
//! no friction traction, so the one static solve with `P` and `Q` together is Cattaneo's
//! problem (the theory allows it; the section in the plane does the same for the disc).

use std::fmt::Write as _;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_contact::{ContactError, ContactProblem, ContactResult, InterfaceNode, NodeStatus};
use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
use vem_mesh::{Point3, PolyhedralMesh};
use vem_scene::{BuiltMesh, ScalarValue, Scene};
use vem_verify::exact::HertzSphere;

type Failure = Box<dyn std::error::Error>;

/// Young's modulus and Poisson's ratio of both blocks.
const YOUNG: f64 = 100.0;
const POISSON: f64 = 0.3;
/// The radius `R` of the gap `r^2 / (2 R)`.
const RADIUS: f64 = 1.0;
/// Coulomb's coefficient.
const COEFFICIENT: f64 = 0.3;
/// Hertz's contact radius the push is chosen for.
const CONTACT_RADIUS: f64 = 0.1;
/// The half-width `L` of the blocks (`[-L, L] x [0, L]`, the plane y = 0 of symmetry) and
/// their height.
const HALF_WIDTH: f64 = 1.0;
/// Beyond `FINE` contact radii from the axis the cells grow by this factor.
const GROWTH: f64 = 1.3;
const FINE: f64 = 1.3;
/// The ratios `Q/(F P)` of the partial slip.
pub const RATIOS: [f64; 3] = [0.2, 0.5, 0.8];
/// The ratio beyond the capacity.
pub const BEYOND: f64 = 1.01;

/// Hertz's contact of the two blocks (`1/E* = 2 (1 - nu^2) / E`) at the push `P` whose
/// contact radius is [`CONTACT_RADIUS`]: `P = 4 E* a^3 / (3 R)`.
pub fn hertz() -> Result<HertzSphere, Failure> {
    let e_star = YOUNG / (2.0 * (1.0 - POISSON * POISSON));
    let push = 4.0 * e_star * CONTACT_RADIUS.powi(3) / (3.0 * RADIUS);
    Ok(HertzSphere::try_new(RADIUS, e_star, push)?)
}

/// Coordinates from 0 to `length`: cells of size `h` up to `fine`, then growing by
/// [`GROWTH`] (the last cell merged with the one before if short).
fn graded(h: f64, fine: f64, length: f64) -> Vec<f64> {
    let mut x = vec![0.0];
    let mut step = h;
    while *x.last().expect("one coordinate") < length - 1e-12 {
        let last = *x.last().expect("one coordinate");
        if last >= fine - 1e-12 {
            step *= GROWTH;
        }
        x.push((last + step).min(length));
    }
    let n = x.len();
    if n > 2 && x[n - 1] - x[n - 2] < 0.5 * step {
        x.remove(n - 2);
    }
    x
}

/// The lattice of hexahedra with its vertex `(i, j, k)` moved to `(xs[i], ys[j], zs[k])`; the
/// sides keep their names (left `x = xs[0]`, front `y = ys[0]`, bottom `z = zs[0]`, ...).
fn lattice(xs: &[f64], ys: &[f64], zs: &[f64]) -> Result<PolyhedralMesh, Failure> {
    let (nx, ny, nz) = (xs.len() - 1, ys.len() - 1, zs.len() - 1);
    let unit = hexahedra(&Cuboid::unit_cube(), nx, ny, nz)?;
    let index = |s: f64, m: usize| (s * m as f64).round() as usize;
    let vertices = unit
        .vertices()
        .iter()
        .map(|p| Point3::new(xs[index(p.x, nx)], ys[index(p.y, ny)], zs[index(p.z, nz)]))
        .collect();
    Ok(PolyhedralMesh::from_compact(
        vertices,
        unit.face_offsets().to_vec(),
        unit.face_vertex_indices().to_vec(),
        unit.cell_offsets().to_vec(),
        unit.cell_face_indices().to_vec(),
        unit.parts().to_vec(),
    )?)
}

/// The scene of the two blocks at the node spacing `h` on the contact zone: the upper block
/// `[-L, L] x [0, L] x [0, L]` and its mirror image below `z = 0`, graded away from the axis
/// and from the interface (given inline); the upper block's top a rigid plate pushed with `P/2`
/// and sheared with `Q/2` along x (half of the load: the plane y = 0 is a plane of symmetry,
/// rollers there), the lower block's bottom clamped, the gap `r^2 / (2 R)`, Coulomb friction.
pub fn scene(h: f64, push: f64, shear: f64) -> Result<Scene, Failure> {
    let half = graded(h, FINE * CONTACT_RADIUS, HALF_WIDTH);
    let xs: Vec<f64> = half
        .iter()
        .rev()
        .map(|x| -x)
        .chain(half.iter().skip(1).copied())
        .collect();
    let up = graded(h, FINE * CONTACT_RADIUS, HALF_WIDTH);
    let down: Vec<f64> = up.iter().rev().map(|z| -z).collect();
    let material = serde_json::json!({ "E": YOUNG, "nu": POISSON });
    let mut scene = Scene::from_value(serde_json::json!({
        "title": "Cattaneo-Mindlin in space: two blocks under a spherical gap",
        "body": [
            { "name": "upper", "mesh": {}, "material": material,
              "dirichlet": [{ "part": "front", "y": 0.0 }],
              "rigid_plate": [
                  { "part": "top", "resultant_z": -0.5 * push },
                  { "part": "top", "resultant_x": 0.5 * shear },
              ] },
            { "name": "lower", "mesh": {}, "material": material,
              "dirichlet": [
                  { "part": "front", "y": 0.0 },
                  { "part": "bottom", "x": 0.0, "y": 0.0, "z": 0.0 },
              ] },
        ],
        "contact": [{
            "body": "upper", "part": "bottom", "other_body": "lower", "other_part": "top",
            "law": { "name": "coulomb", "coefficient": COEFFICIENT },
        }],
    }))?;
    scene.bodies[0].mesh = BuiltMesh::Space(lattice(&xs, &half, &up)?).to_inline();
    scene.bodies[1].mesh = BuiltMesh::Space(lattice(&xs, &half, &down)?).to_inline();
    scene.contacts[0].imposed_gap = Some(ScalarValue::function(|x, _| {
        (x[0] * x[0] + x[1] * x[1]) / (2.0 * RADIUS)
    }));
    Ok(scene)
}

/// The contact problem of [`scene`] as `vem_scene::Model::build` makes it, and the scene's
/// solver.
pub fn problem(
    h: f64,
    push: f64,
    shear: f64,
) -> Result<(ContactProblem<3>, Box<dyn vem_contact::ContactSolver>), Failure> {
    let (model, solver) = super::model(&scene(h, push, shear)?)?;
    let (problem, _) = model
        .contact_problem_3d()
        .ok_or("the scene has no contact pair in space")?;
    Ok((problem.clone(), solver))
}

/// The distance of a node to the axis.
fn radius(n: &InterfaceNode<3>) -> f64 {
    n.position.x.hypot(n.position.y)
}

/// One ratio `Q/(F P)`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MindlinRow {
    /// `Q/(F P)`.
    pub ratio: f64,
    /// The largest distance to the axis of a node that sticks.
    pub stick_radius: f64,
    /// The smallest distance to the axis of a node in contact that slips (infinite, `null` in
    /// JSON, when none slips).
    #[serde(deserialize_with = "super::number_or_infinity")]
    pub innermost_slip: f64,
    /// Cattaneo-Mindlin's `c = a (1 - Q/(F P))^(1/3)`.
    pub mindlin: f64,
    /// The largest distance to the axis of a node in contact, and Hertz's `a`.
    pub contact_radius: f64,
    /// `|(sum of the friction forces on the upper block) + Q/2| / (Q/2)`.
    pub shear_error: f64,
    /// `|(sum of the normal forces) - P/2| / (P/2)`.
    pub push_error: f64,
    /// Stick and slip nodes.
    pub stick_nodes: usize,
    /// Nodes in contact that slip.
    pub slip_nodes: usize,
    /// Coulomb's fixed-point steps.
    pub steps: usize,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// The study at the node spacing `h`: every ratio of [`RATIOS`], then [`BEYOND`].
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Mindlin {
    /// The node spacing on the contact zone.
    pub h: f64,
    /// Hertz's contact radius `a`.
    pub a: f64,
    /// The push `P` (whole: twice the half model's).
    pub push: f64,
    /// Unknowns of the two blocks.
    pub unknowns: usize,
    /// The partial slips.
    pub rows: Vec<MindlinRow>,
    /// What the solve beyond the capacity answered.
    pub beyond: String,
    /// True when the solve beyond the capacity was refused with `FrictionCapacityExceeded`.
    pub refused: bool,
}

fn row(result: &ContactResult<3>, ratio: f64, hertz: &HertzSphere, seconds: f64) -> MindlinRow {
    let (push, shear) = (hertz.load(), ratio * COEFFICIENT * hertz.load());
    let with = |status: NodeStatus| result.nodes.iter().filter(move |n| n.status == status);
    let friction = result.friction_resultant();
    MindlinRow {
        ratio,
        stick_radius: with(NodeStatus::Stick).map(radius).fold(0.0, f64::max),
        innermost_slip: with(NodeStatus::Slip)
            .filter(|n| n.normal_force > 0.0)
            .map(radius)
            .fold(f64::INFINITY, f64::min),
        mindlin: hertz.stick_radius(ratio),
        contact_radius: result
            .nodes
            .iter()
            .filter(|n| n.normal_force > 0.0)
            .map(radius)
            .fold(0.0, f64::max),
        shear_error: (friction.x + 0.5 * shear).abs() / (0.5 * shear),
        push_error: (result.normal_resultant() - 0.5 * push).abs() / (0.5 * push),
        stick_nodes: with(NodeStatus::Stick).count(),
        slip_nodes: with(NodeStatus::Slip).count(),
        steps: result.fixed_point.as_ref().map_or(0, |f| f.steps),
        seconds,
    }
}

/// Runs the study at the node spacing `h` (`a / 6` in the full run, `a / 4` quick).
pub fn study(h: f64) -> Result<Mindlin, Failure> {
    let hertz = hertz()?;
    let push = hertz.load();
    let mut rows = Vec::new();
    let mut unknowns = 0;
    for ratio in RATIOS {
        let start = Instant::now();
        let (problem, mut solver) = problem(h, push, ratio * COEFFICIENT * push)?;
        let result = problem.solve(solver.as_mut())?;
        unknowns = result
            .bodies
            .iter()
            .map(|b| b.body.dofs().n_unknowns())
            .sum();
        rows.push(row(&result, ratio, &hertz, start.elapsed().as_secs_f64()));
    }
    let (problem, mut solver) = problem(h, push, BEYOND * COEFFICIENT * push)?;
    let beyond = problem.solve(solver.as_mut());
    let refused = matches!(beyond, Err(ContactError::FrictionCapacityExceeded { .. }));
    let beyond = match beyond {
        Ok(result) => format!(
            "solved ({:?}): Q/(F P) = {BEYOND} was not refused",
            result.report.status
        ),
        Err(e) => e.to_string(),
    };
    Ok(Mindlin {
        h,
        a: hertz.contact_radius(),
        push,
        unknowns,
        rows,
        beyond,
        refused,
    })
}

impl Mindlin {
    /// The shortfalls: a stick radius more than one node spacing from Mindlin's, a load not
    /// carried to 1e-8, no refusal beyond the capacity.
    pub fn shortfalls(&self) -> Vec<String> {
        let mut out = Vec::new();
        for r in &self.rows {
            if (r.stick_radius - r.mindlin).abs() > self.h {
                out.push(format!(
                    "Q/(F P) = {}: stick radius {:.4} against c = {:.4}, more than h = {:.4} apart",
                    r.ratio, r.stick_radius, r.mindlin, self.h
                ));
            }
            if !(r.shear_error <= 1e-8 && r.push_error <= 1e-8) {
                out.push(format!(
                    "Q/(F P) = {}: load carried to {:.1e} (Q), {:.1e} (P)",
                    r.ratio, r.shear_error, r.push_error
                ));
            }
        }
        if !self.refused {
            out.push(format!(
                "Q/(F P) = {BEYOND}: not refused with FrictionCapacityExceeded: {}",
                self.beyond
            ));
        }
        out
    }

    /// The Markdown table.
    pub fn markdown(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Two blocks `[-1, 1] x [0, 1] x (0, 1)` and its mirror image (half model, the plane \
             y = 0 of symmetry), E = {YOUNG}, nu = {POISSON}, gap `r^2/(2R)`, R = {RADIUS}, \
             F = {COEFFICIENT}, P = {:.6} (Hertz's a = {:.3}), node spacing h = {:.5} = a/{:.0} \
             on the contact zone, {} unknowns, condensed solver.\n",
            self.push,
            self.a,
            self.h,
            self.a / self.h,
            self.unknowns
        );
        let _ = writeln!(
            out,
            "| Q/(F P) | outermost stick node r | innermost slip node r | c = a (1 - Q/(F P))^(1/3) \
             | (r_stick - c) / h | outermost contact node r / a | Q carried | P carried | stick / \
             slip nodes | fixed-point steps | seconds |\n|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|"
        );
        for r in &self.rows {
            let _ = writeln!(
                out,
                "| {} | {:.4} | {:.4} | {:.4} | {:+.2} | {:.3} | {:.1e} | {:.1e} | {} / {} | {} | {:.1} |",
                r.ratio,
                r.stick_radius,
                r.innermost_slip,
                r.mindlin,
                (r.stick_radius - r.mindlin) / self.h,
                r.contact_radius / self.a,
                r.shear_error,
                r.push_error,
                r.stick_nodes,
                r.slip_nodes,
                r.steps,
                r.seconds
            );
        }
        let _ = writeln!(out, "\nQ/(F P) = {BEYOND}: {}", self.beyond);
        out
    }
}

/// `mindlin-3d.json`: the study and how it was run.
#[derive(Debug, Serialize, Deserialize)]
pub struct Section {
    /// The options of the run: `" --quick"` or nothing.
    pub options: String,
    /// Wall-clock seconds of the section.
    pub seconds: f64,
    /// The study.
    pub study: Mindlin,
}

/// The files of the section rendered from its JSON: `mindlin-3d.md`, its template
/// (`xtask/templates/mindlin-3d.md`) filled with the study's table and verdict.
pub fn report(section: &Section) -> Result<Vec<(String, String)>, Failure> {
    let shortfalls = section.study.shortfalls();
    let md = crate::common::render(
        "xtask/templates/mindlin-3d.md",
        include_str!("../../templates/mindlin-3d.md"),
        &[
            ("options", section.options.clone()),
            ("seconds", format!("{:.0}", section.seconds)),
            ("study", section.study.markdown()),
            (
                "verdict",
                if shortfalls.is_empty() {
                    "pass (every stick radius within one node spacing of Mindlin's, the load \
                     carried to 1e-8, the refusal beyond the capacity)."
                        .to_string()
                } else {
                    format!("FAIL\n\n- {}", shortfalls.join("\n- "))
                },
            ),
        ],
    )?;
    Ok(vec![("mindlin-3d.md".to_string(), md)])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quick variant: at h = a/4 the stick radius is within one node spacing of Mindlin's
    /// at the three ratios and the load is carried to 1e-8; Q = 1.01 F P gets no answer (refused
    /// with `FrictionCapacityExceeded` by the capacity check of Coulomb's fixed point, as the
    /// same blocks are in `crates/vem-contact/tests/friction_3d.rs`).
    #[test]
    fn the_quick_cattaneo_mindlin_in_space_finds_the_stick_disc() {
        let hertz = hertz().unwrap();
        let study = study(hertz.contact_radius() / 4.0).unwrap();
        println!("{}", study.markdown());
        assert_eq!(study.rows.len(), RATIOS.len());
        for r in &study.rows {
            assert!((r.stick_radius - r.mindlin).abs() <= study.h, "{r:?}");
            assert!(r.shear_error <= 1e-8 && r.push_error <= 1e-8, "{r:?}");
        }
        assert!(!study.beyond.starts_with("solved"), "{}", study.beyond);
        let shortfalls = study.shortfalls();
        assert!(study.refused || shortfalls.len() == 1, "{shortfalls:?}");
    }
}
