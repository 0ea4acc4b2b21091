//! The rows in the plane: two-body linear patch tests at every Poisson ratio up to 0.49999, at
//! stiffness contrasts, on degenerate cells and at extreme gaps and penalty factors; the
//! invariances of M1 and M2 under scaled lengths and moduli and of Tresca with a zero bound;
//! the locking measure on E2 and E2c; the shipped Hertz scene near incompressibility.

use std::path::Path;
use std::sync::Arc;

use vem_contact::{
    ContactError, ContactLaw, ContactNode, ContactProblem, ContactResult, Frictionless, LawState,
    PenaltyParameter, SolverRegistry, Tresca,
};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Mesh, PartSpec, Point, Vector};
use vem_scene::description::{
    BodyDescription, ContactDescription, DirichletDescription, MaterialDescription,
    PlaneDescription, TractionDescription,
};
use vem_scene::{BuildOptions, BuiltMesh, Model, ScalarValue, Scene, VectorValue};
use vem_space::{Choice, ElementRegistry, ElementSpace, Options};

use super::{
    chain, judge, locking_row, one_outcome, patch_tolerance, solve, Outcome, Row, Size, Verdict,
    LOCKING_RATIO, POISSON_RATIOS, SAME_PROBLEM_TOLERANCE, UNITS_TOLERANCE,
};
use crate::cases::{CaseRegistry, PATCH_TOLERANCE};
use crate::exact::{BodyId, ExactContact, ExactSolution, Lame, Side};
use crate::nalgebra::Matrix2;
use crate::norms::ErrorNorms;
use crate::problem::{registries_with, DiscreteProblem, ProblemSettings, ELEMENT, LAW};

// ---------------------------------------------------------------------------------------------
// Two-body linear patch tests

/// A uniform stress state in each body and the matching linear displacement.
#[derive(Debug, Clone, Copy)]
struct LinearField {
    /// Displacement gradient (i, j) = d_j u_i.
    gradient: [[f64; 2]; 2],
    /// Translation.
    offset: [f64; 2],
    /// Stress.
    stress: [[f64; 2]; 2],
}

impl LinearField {
    /// Plane strain, stress `[[sxx, q], [q, syy]]`, rotation chosen so that d_x u_y = 0
    /// (the interface `y = 0` moves as a rigid translation of each body when d_x u_x = 0).
    fn new(lambda: f64, mu: f64, sxx: f64, syy: f64, q: f64, offset: [f64; 2]) -> Self {
        let det = 4.0 * mu * (lambda + mu);
        let exx = ((lambda + 2.0 * mu) * sxx - lambda * syy) / det;
        let eyy = ((lambda + 2.0 * mu) * syy - lambda * sxx) / det;
        let exy = q / (2.0 * mu);
        Self {
            gradient: [[exx, 2.0 * exy], [0.0, eyy]],
            offset,
            stress: [[sxx, q], [q, syy]],
        }
    }

    fn displacement(&self, x: Point) -> Vector {
        let g = &self.gradient;
        Vector::new(
            g[0][0] * x.x + g[0][1] * x.y + self.offset[0],
            g[1][0] * x.x + g[1][1] * x.y + self.offset[1],
        )
    }

    fn traction(&self, normal: Vector) -> Vector {
        let s = &self.stress;
        Vector::new(
            s[0][0] * normal.x + s[0][1] * normal.y,
            s[1][0] * normal.x + s[1][1] * normal.y,
        )
    }
}

/// Mesh kinds of the patch tests (each body meshed on its own, interface at `y = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cells {
    /// Structured quads.
    Quads,
    /// Structured quads, each cut into two triangles.
    Triangles,
    /// Every cell an octagon with four edges `ratio` times the cell size (straight angles).
    TinyEdges(f64),
    /// A layer of cells `ratio` times thinner than wide along the interface.
    Layer(f64),
    /// A layer of flat triangles (height `ratio` times the base, apex over the middle) along
    /// the interface, with needles between them.
    Slivers(f64),
    /// Every other row made of chevrons whose reflex vertex is `ratio` times the cell size
    /// above the bottom edge (non-convex, close to degenerate).
    Chevrons(f64),
}

impl Cells {
    fn describe(self) -> String {
        match self {
            Cells::Quads => "quads".to_string(),
            Cells::Triangles => "triangles".to_string(),
            Cells::TinyEdges(r) => format!("edges {r:.0e} of the diameter"),
            Cells::Layer(r) => format!("aspect ratio {:.0e}", 1.0 / r),
            Cells::Slivers(r) => format!("slivers, height/base {r:.0e}"),
            Cells::Chevrons(r) => format!("chevrons, reflex vertex {r:.0e} h off the edge"),
        }
    }
}

/// A mesh of `(0, width) x (0, height)` (interface at the bottom), then mirrored to
/// `(0, width) x (-height, 0)` when `mirror` (interface at the top).
fn patch_mesh(
    cells: Cells,
    width: f64,
    height: f64,
    n: usize,
    mirror: bool,
) -> Result<Mesh, String> {
    let h = width / n as f64;
    let xs: Vec<f64> = (0..=n).map(|i| width * i as f64 / n as f64).collect();
    let mut points: Vec<Point> = Vec::new();
    let mut polygons: Vec<Vec<usize>> = Vec::new();
    let lattice = |ys: &[f64], points: &mut Vec<Point>| -> usize {
        let start = points.len();
        for &y in ys {
            for &x in &xs {
                points.push(Point::new(x, y));
            }
        }
        start
    };
    let uniform = |from: f64, rows: usize| -> Vec<f64> {
        (0..=rows)
            .map(|j| from + (height - from) * j as f64 / rows as f64)
            .collect()
    };
    let row = n + 1;
    match cells {
        Cells::Quads | Cells::Triangles | Cells::Layer(_) | Cells::Chevrons(_) => {
            let ys = match cells {
                Cells::Layer(r) => {
                    let mut ys = vec![0.0];
                    ys.extend(uniform(r * h, n.max(2) - 1));
                    ys
                }
                _ => uniform(0.0, n),
            };
            let start = lattice(&ys, &mut points);
            let v = |i: usize, j: usize| start + j * row + i;
            let rows = ys.len() - 1;
            for j in 0..rows {
                for i in 0..n {
                    match cells {
                        Cells::Chevrons(r) if j % 2 == 0 && j + 1 < rows => {
                            let c = points.len();
                            points.push(Point::new(0.5 * (xs[i] + xs[i + 1]), ys[j] + r * h));
                            polygons.push(vec![
                                v(i, j),
                                v(i + 1, j),
                                v(i + 1, j + 1),
                                c,
                                v(i, j + 1),
                            ]);
                        }
                        Cells::Chevrons(_) if j % 2 == 1 => {
                            // The reflex vertex of the chevron below is on this cell's bottom.
                            let c = start + ys.len() * row + (j / 2) * n + i;
                            polygons.push(vec![
                                v(i, j),
                                c,
                                v(i + 1, j),
                                v(i + 1, j + 1),
                                v(i, j + 1),
                            ]);
                        }
                        Cells::Triangles => {
                            polygons.push(vec![v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                            polygons.push(vec![v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
                        }
                        _ => {
                            polygons.push(vec![v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)])
                        }
                    }
                }
            }
        }
        Cells::TinyEdges(r) => {
            let ys = uniform(0.0, n);
            let start = lattice(&ys, &mut points);
            let v = |i: usize, j: usize| start + j * row + i;
            // Extra points on horizontal edges (i in 0..n, j in 0..=n), then vertical ones.
            let horizontal = points.len();
            for &y in &ys {
                for &x in &xs[..n] {
                    points.push(Point::new(x + r * h, y));
                }
            }
            let vertical = points.len();
            for &y in &ys[..n] {
                for &x in &xs {
                    points.push(Point::new(x, y + r * h));
                }
            }
            let eh = |i: usize, j: usize| horizontal + j * n + i;
            let ev = |i: usize, j: usize| vertical + j * row + i;
            for j in 0..n {
                for i in 0..n {
                    polygons.push(vec![
                        v(i, j),
                        eh(i, j),
                        v(i + 1, j),
                        ev(i + 1, j),
                        v(i + 1, j + 1),
                        eh(i, j + 1),
                        v(i, j + 1),
                        ev(i, j),
                    ]);
                }
            }
        }
        Cells::Slivers(r) => {
            let t = r * h;
            let mut ys = vec![t];
            ys.extend(uniform(t, n.max(2) - 1).into_iter().skip(1));
            let bottom = points.len();
            for &x in &xs {
                points.push(Point::new(x, 0.0));
            }
            let middle = points.len();
            for i in 0..n {
                points.push(Point::new(0.5 * (xs[i] + xs[i + 1]), t));
            }
            let start = lattice(&ys, &mut points);
            let v = |i: usize, j: usize| start + j * row + i;
            for i in 0..n {
                let (b0, b1, m) = (bottom + i, bottom + i + 1, middle + i);
                polygons.push(vec![b0, b1, m]);
                polygons.push(vec![b0, m, v(i, 0)]);
                polygons.push(vec![b1, v(i + 1, 0), m]);
            }
            for j in 0..ys.len() - 1 {
                for i in 0..n {
                    let mut polygon = vec![v(i, j)];
                    if j == 0 {
                        polygon.push(middle + i);
                    }
                    polygon.extend([v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
                    polygons.push(polygon);
                }
            }
        }
    }
    if mirror {
        for p in &mut points {
            p.y = -p.y;
        }
        for polygon in &mut polygons {
            polygon.reverse();
        }
    }
    let (ymin, ymax) = if mirror {
        (-height, 0.0)
    } else {
        (0.0, height)
    };
    let tol = 1e-13 * width.max(height);
    let on = |a: f64, b: f64| (a - b).abs() <= tol;
    let mut parts: Vec<PartSpec> = ["left", "right", "bottom", "top"]
        .iter()
        .map(|name| PartSpec::new(*name, Vec::new()))
        .collect();
    for polygon in &polygons {
        for k in 0..polygon.len() {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let (pa, pb) = (points[a], points[b]);
            let side = if on(pa.x, 0.0) && on(pb.x, 0.0) {
                0
            } else if on(pa.x, width) && on(pb.x, width) {
                1
            } else if on(pa.y, ymin) && on(pb.y, ymin) {
                2
            } else if on(pa.y, ymax) && on(pb.y, ymax) {
                3
            } else {
                continue;
            };
            parts[side].edges.push([a, b]);
        }
    }
    Mesh::from_polygons(points, &polygons, parts).map_err(|e| format!("mesh: {}", chain(&e)))
}

/// A two-body linear patch test: body 1 = (0, W) x (0, H) above body 2 = (0, W) x (-H, 0),
/// uniform stress `[[sxx_i, q], [q, -p]]` in body i, body 1's top and body 2's bottom
/// prescribed, the lateral sides loaded by the exact tractions, the interface `y = 0` in
/// contact with the imposed gap `h0 = [u]_nu + opening`.
#[derive(Clone)]
struct Patch {
    length: f64,
    lame: [(f64, f64); 2],
    /// Compression `p = -sigma_yy` (both bodies).
    pressure: f64,
    /// Shear stress `sigma_xy` (both bodies).
    shear: f64,
    /// `sigma_xx` per body: `None` makes `d_x u_x = 0` (no tangential jump from the contrast).
    lateral: Option<f64>,
    /// Translation of body 1 (body 2 has none).
    offset: [f64; 2],
    /// The gap beyond the exact normal jump (0: in contact where pressed).
    opening: f64,
    law: Arc<dyn ContactLaw>,
    cells: Cells,
    /// Both bodies on the same number of cells across (no interface node insertion).
    matching: bool,
    element: Arc<dyn ElementSpace>,
}

impl Patch {
    /// Frictionless, pressed (p = 1/100 of the modulus of body 2), unit square bodies.
    fn pressed(lame: [(f64, f64); 2], n_cells: Cells) -> Self {
        let modulus = lame[1].0 + 2.0 * lame[1].1;
        Self {
            length: 1.0,
            lame,
            pressure: 0.01 * modulus,
            shear: 0.0,
            lateral: None,
            offset: [0.003, 0.0],
            opening: 0.0,
            law: Arc::new(Frictionless),
            cells: n_cells,
            matching: false,
            element: default_element(),
        }
    }

    fn fields(&self) -> [LinearField; 2] {
        let p = self.pressure;
        let field = |k: usize, offset: [f64; 2]| {
            let (lambda, mu) = self.lame[k];
            let sxx = self.lateral.unwrap_or(-lambda * p / (lambda + 2.0 * mu));
            LinearField::new(lambda, mu, sxx, -p, self.shear, offset)
        };
        let l = self.length;
        [
            field(0, [self.offset[0] * l, self.offset[1] * l]),
            field(1, [0.0, 0.0]),
        ]
    }

    /// The exact normal resultant (sum of compressive nodal forces).
    fn resultant(&self) -> f64 {
        self.pressure * self.length
    }

    /// The problem as a scene: the two bodies with their meshes inline, the exact displacement
    /// on the held sides and the constant tractions on the lateral sides, the pair with the
    /// patch's law and constant imposed gap; the contact problem of its model.
    fn problem(&self, n: usize) -> Result<ContactProblem, String> {
        let fields = self.fields();
        let l = self.length;
        let registries = registries_with(Some(Arc::clone(&self.element)), Some(self.law.clone()))
            .map_err(|e| chain(&e))?;
        let mut scene = Scene::default();
        for (k, field) in fields.iter().enumerate() {
            let across = if self.matching { n } else { n + k };
            let mesh = patch_mesh(self.cells, l, l, across, k == 1)?;
            let (lambda, mu) = self.lame[k];
            let field = *field;
            let component = |i: usize| {
                Some(ScalarValue::function(move |x, _| {
                    field.displacement(Point::new(x[0], x[1]))[i]
                }))
            };
            let traction = |part: &str, nx: f64| {
                let g = field.traction(Vector::new(nx, 0.0));
                TractionDescription {
                    part: part.to_string(),
                    value: Some(VectorValue::constant(&[g.x, g.y])),
                    ..TractionDescription::default()
                }
            };
            scene.bodies.push(BodyDescription {
                name: format!("patch-body-{}", k + 1),
                mesh: BuiltMesh::Plane(mesh).to_inline(),
                material: MaterialDescription {
                    lambda: Some(lambda),
                    mu: Some(mu),
                    plane: Some(PlaneDescription::Strain),
                    ..MaterialDescription::default()
                },
                element: Some(Choice::named(ELEMENT)),
                dirichlet: vec![DirichletDescription {
                    part: if k == 0 { "top" } else { "bottom" }.to_string(),
                    x: component(0),
                    y: component(1),
                    ..DirichletDescription::default()
                }],
                traction: vec![traction("left", -1.0), traction("right", 1.0)],
                ..BodyDescription::default()
            });
        }
        // [u]_nu = u_1 . (0, -1) + u_2 . (0, 1) on y = 0: constant (d_x u_y = 0).
        let origin = Point::new(0.0, 0.0);
        let jump = -fields[0].displacement(origin).y + fields[1].displacement(origin).y;
        scene.contacts.push(ContactDescription {
            body: "patch-body-1".to_string(),
            part: "bottom".to_string(),
            other_body: Some("patch-body-2".to_string()),
            other_part: Some("top".to_string()),
            law: Some(Choice::named(LAW)),
            imposed_gap: Some(ScalarValue::Constant(jump + self.opening * l)),
            ..ContactDescription::default()
        });
        let options = BuildOptions {
            registries,
            ..BuildOptions::default()
        };
        let model = Model::build(&scene, &options).map_err(|e| chain(&e))?;
        let (problem, _) = model.contact_problem().ok_or("no contact pair")?;
        Ok(problem.clone())
    }

    /// Largest nodal displacement error relative to the body's largest exact displacement,
    /// over both bodies, and the normal resultant's error relative to the force scale.
    fn errors(&self, result: &ContactResult) -> (f64, f64) {
        let fields = self.fields();
        let mut worst: f64 = 0.0;
        for (body, field) in result.bodies.iter().zip(&fields) {
            let mesh = body.body.mesh();
            let u = body.solution.displacement();
            let (mut error, mut scale): (f64, f64) = (0.0, 0.0);
            for (v, &x) in mesh.vertices().iter().enumerate() {
                let exact = field.displacement(x);
                scale = scale.max(exact.x.abs()).max(exact.y.abs());
                error = error
                    .max((u[2 * v] - exact.x).abs())
                    .max((u[2 * v + 1] - exact.y).abs());
            }
            worst = worst.max(if scale > 0.0 { error / scale } else { error });
        }
        let force_scale = fields
            .iter()
            .flat_map(|f| f.stress.iter().flatten())
            .fold(0.0_f64, |m, s| m.max(s.abs()))
            * self.length;
        let resultant_error = (result.normal_resultant() - self.resultant()).abs();
        let force = if force_scale > 0.0 {
            resultant_error / force_scale
        } else {
            resultant_error
        };
        (worst, force)
    }

    /// Solves with `solver` (options `options`) and judges against the exact answer within
    /// `tolerance`.
    fn judge(&self, n: usize, solver: &str, options: &Options, tolerance: f64) -> Outcome {
        let outcome = self
            .problem(n)
            .and_then(|problem| solve(&problem, solver, options));
        let measured = |r: &ContactResult| {
            let (u, f) = self.errors(r);
            (
                format!("max nodal error {u:.1e}, resultant error {f:.1e}"),
                u <= tolerance && f <= tolerance,
            )
        };
        judge(solver, outcome, measured)
    }
}

fn default_element() -> Arc<dyn ElementSpace> {
    ElementRegistry::builtin()
        .make(ElementRegistry::DEFAULT)
        .expect("the default element is registered")
}

/// Relative difference allowed between two answers of `solver` to the same problem posed two
/// ways: [`SAME_PROBLEM_TOLERANCE`], or for the exact solver the complementarity its
/// acceptance test certifies (an interior point stops at a barrier parameter of about its
/// tolerance, and a weakly active node's force and gap are accurate to its square root).
pub fn same_problem_tolerance(solver: &str) -> f64 {
    if solver == "exact" {
        vem_contact::ExactSettings::default()
            .acceptance()
            .complementarity
            .max(SAME_PROBLEM_TOLERANCE)
    } else {
        SAME_PROBLEM_TOLERANCE
    }
}

fn patch_row(name: String, patch: &Patch, size: &Size) -> Row {
    let outcomes = size
        .solvers
        .iter()
        .map(|s| patch.judge(size.patch, s, &Options::new(), patch_tolerance(s)))
        .collect();
    Row {
        name,
        expected: format!(
            "exact linear field: nodal error and resultant error <= {PATCH_TOLERANCE:.0e} \
             (penalty: <= 1e-3 = 1/factor)"
        ),
        outcomes,
    }
}

fn lame_of(nu: f64) -> (f64, f64) {
    // mu = 1, lambda = 2 mu nu / (1 - 2 nu).
    (2.0 * nu / (1.0 - 2.0 * nu), 1.0)
}

// ---------------------------------------------------------------------------------------------
// Groups

/// Poisson ratio sweep for every element of the registry: the contact patch test (exact, every
/// solver) and the locking measure on E2 (errors at nu against nu = 0.3).
pub fn poisson(size: &Size) -> Vec<Row> {
    let elements = ElementRegistry::builtin();
    let mut rows = Vec::new();
    for name in elements.names() {
        let element = elements.make(name).expect("a registered element");
        for &nu in &POISSON_RATIOS[1..] {
            let lame = lame_of(nu);
            let mut patch = Patch::pressed([lame, lame], Cells::Quads);
            patch.element = Arc::clone(&element);
            let mut row = patch_row(
                format!("{name}: contact patch test on quads, nu = {nu}"),
                &patch,
                size,
            );
            // Elements limited to triangles (p1) refuse the quads: run them on matching
            // triangles (an inserted node would make a triangle a quadrilateral).
            if row
                .outcomes
                .iter()
                .all(|o| matches!(&o.verdict, Verdict::Refused(e) if e.contains("support")))
            {
                patch.cells = Cells::Triangles;
                patch.matching = true;
                row = patch_row(
                    format!("{name}: contact patch test on matching triangles, nu = {nu}"),
                    &patch,
                    size,
                );
            }
            rows.push(row);
        }
        rows.extend(locking(name, &element, size));
    }
    rows
}

/// E2 errors (E_grad, E_0 relative) at every nu against nu = 0.3 on each family.
fn locking(name: &str, element: &Arc<dyn ElementSpace>, size: &Size) -> Vec<Row> {
    let cases = CaseRegistry::builtin();
    let settings = ProblemSettings::builder()
        .element(Arc::clone(element))
        .build()
        .expect("valid settings");
    let mut rows = Vec::new();
    for family in &size.locking_families {
        let errors = |nu: f64| -> Result<ErrorNorms, String> {
            let (lambda, mu) = lame_of(nu);
            let lame = Lame::try_new(lambda, mu).map_err(|e| chain(&e))?;
            let exact = cases.make("E2", lame).map_err(|e| chain(&e))?;
            let mesh = family
                .generate(&exact.domain(BodyId::One), size.locking, 1)
                .map_err(|e| chain(&e))?;
            let problem = DiscreteProblem::try_new(Arc::clone(&exact), vec![mesh], &settings)
                .map_err(|e| chain(&e))?;
            let mut unused = vem_contact::CondensedSolver::default();
            let solution = problem.solve(&mut unused).map_err(|e| chain(&e))?;
            let parts = solution.errors(&*exact).map_err(|e| chain(&e))?;
            Ok(ErrorNorms::combine(&parts))
        };
        let reference = match errors(0.3) {
            Ok(e) => e,
            Err(error) if error.contains("support") => continue,
            Err(error) => {
                rows.push(Row {
                    name: format!("{name}: E2 on {}, nu = 0.3", family.name()),
                    expected: "a solution".to_string(),
                    outcomes: vec![Outcome {
                        solver: "elasticity (Cholesky)".to_string(),
                        measured: format!("error: {error}"),
                        verdict: Verdict::Refused(error),
                    }],
                });
                continue;
            }
        };
        let mut outcomes = Vec::new();
        let mut worst: (f64, f64, f64) = (0.0, 0.0, 0.3);
        let mut refused = None;
        for &nu in &POISSON_RATIOS[1..] {
            match errors(nu) {
                Ok(e) => {
                    let g = e.relative_grad() / reference.relative_grad();
                    let l = e.relative_l2() / reference.relative_l2();
                    if g.max(l) > worst.0.max(worst.1) {
                        worst = (g, l, nu);
                    }
                }
                Err(error) => refused = Some(format!("nu = {nu}: {error}")),
            }
        }
        let (g, l, nu) = worst;
        let ok = g <= LOCKING_RATIO && l <= LOCKING_RATIO;
        outcomes.push(Outcome {
            solver: "elasticity (Cholesky)".to_string(),
            measured: match &refused {
                Some(e) => format!("error: {e}"),
                None => format!(
                    "worst at nu = {nu}: E_grad x{g:.2}, E_0 x{l:.2} (E_grad at 0.3: {:.2e})",
                    reference.relative_grad()
                ),
            },
            verdict: match refused {
                Some(e) => Verdict::Refused(e),
                // An element that locks answers what it computes: no solver claims anything.
                None if ok => Verdict::Pass,
                None => Verdict::Warned("locking: the element's error grows with lambda".into()),
            },
        });
        rows.push(Row {
            name: format!(
                "{name}: locking on E2, {}, nu = 0.3 .. 0.49999",
                family.name()
            ),
            expected: format!(
                "relative E_grad and E_0 within {LOCKING_RATIO}x of those at nu = 0.3"
            ),
            outcomes,
        });
    }
    rows
}

/// Stiffness contrasts: body 1 = c times body 2 (lambda = 2, mu = 1), frictionless pressed
/// and Tresca tied (bound 10 times the shear stress).
pub fn contrast(size: &Size) -> Vec<Row> {
    let mut rows = Vec::new();
    for c in [1e4, 1e-4, 1e8, 1e-8] {
        let lame = [(2.0 * c, c), (2.0, 1.0)];
        let patch = Patch::pressed(lame, Cells::Quads);
        rows.push(patch_row(
            format!("E_1/E_2 = {c:.0e}, frictionless"),
            &patch,
            size,
        ));
        let mut tied = Patch::pressed(lame, Cells::Quads);
        tied.shear = 0.5 * tied.pressure;
        tied.offset = [0.0, 0.0];
        tied.law = Arc::new(Tresca::try_new(10.0 * tied.shear).expect("valid bound"));
        rows.push(patch_row(
            format!("E_1/E_2 = {c:.0e}, Tresca stick"),
            &tied,
            size,
        ));
    }
    rows
}

/// Units: M1 (frictionless) and M2 (Tresca) with lengths scaled by 1e6 and 1e-6 and moduli by
/// 1e-9: displacements scale with the lengths, forces with lengths times moduli.
pub fn units(size: &Size) -> Vec<Row> {
    let mut rows = Vec::new();
    for case in ["M1", "M2"] {
        for (length, modulus) in [(1e6, 1.0), (1e-6, 1.0), (1.0, 1e-9), (1e-6, 1e-9)] {
            let outcomes = size
                .solvers
                .iter()
                .map(|solver| units_outcome(case, length, modulus, size.manufactured, solver))
                .collect();
            rows.push(Row {
                name: format!("{case}: lengths x {length:.0e}, moduli x {modulus:.0e}"),
                expected: format!(
                    "displacements / s and nodal forces / (s m) equal the unscaled ones \
                     (relative change <= {UNITS_TOLERANCE:.0e})"
                ),
                outcomes,
            });
        }
    }
    rows
}

fn units_outcome(case: &str, length: f64, modulus: f64, n: usize, solver: &str) -> Outcome {
    let run = |s: f64, m: f64| -> Result<ContactResult, String> {
        let inner = CaseRegistry::builtin()
            .make(case, Lame::default())
            .map_err(|e| chain(&e))?;
        let exact: Arc<dyn ExactSolution> = Arc::new(Scaled {
            inner,
            length: s,
            modulus: m,
        });
        let meshes = [(BodyId::One, n), (BodyId::Two, n + n / 2)]
            .iter()
            .map(|&(body, cells)| MeshFamily::Quads.generate(&exact.domain(body), cells, 1))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| chain(&e))?;
        let problem = DiscreteProblem::try_new(exact, meshes, &ProblemSettings::default())
            .map_err(|e| chain(&e))?;
        let contact = problem.contact_problem().ok_or("not a contact case")?;
        solve(&contact, solver, &Options::new())
    };
    let reference = match run(1.0, 1.0) {
        Ok(r) => r,
        Err(e) => {
            return Outcome {
                solver: solver.to_string(),
                measured: format!("error (unscaled run): {e}"),
                verdict: Verdict::Refused(e),
            }
        }
    };
    let scaled = run(length, modulus);
    judge(solver, scaled, |r| {
        let change = answer_change(&reference, r, length, modulus);
        (
            format!("relative change {change:.1e}"),
            change <= UNITS_TOLERANCE,
        )
    })
}

/// Largest relative change between `a` and `b` (b's displacements divided by `length`, its
/// forces by `length * modulus`): displacements relative to the largest displacement, forces
/// to the largest force.
fn answer_change(a: &ContactResult, b: &ContactResult, length: f64, modulus: f64) -> f64 {
    let ua: Vec<f64> = a
        .bodies
        .iter()
        .flat_map(|r| r.solution.displacement().to_vec())
        .collect();
    let ub: Vec<f64> = b
        .bodies
        .iter()
        .flat_map(|r| r.solution.displacement().to_vec())
        .collect();
    let fa: Vec<f64> = a
        .nodes
        .iter()
        .flat_map(|n| [n.normal_force, n.friction_t()])
        .collect();
    let fb: Vec<f64> = b
        .nodes
        .iter()
        .flat_map(|n| [n.normal_force, n.friction_t()])
        .collect();
    if ua.len() != ub.len() || fa.len() != fb.len() {
        return f64::INFINITY;
    }
    let change = |x: &[f64], y: &[f64], unit: f64| {
        let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let diff = x
            .iter()
            .zip(y)
            .fold(0.0_f64, |m, (p, q)| m.max((p - q / unit).abs()));
        if scale > 0.0 {
            diff / scale
        } else {
            diff
        }
    };
    change(&ua, &ub, length).max(change(&fa, &fb, length * modulus))
}

/// Degenerate cells in both bodies (matching neither each other nor in size), pressed
/// frictionless and Tresca full slip.
pub fn cells(size: &Size) -> Vec<Row> {
    let kinds = [
        Cells::TinyEdges(1e-8),
        Cells::Layer(1e-3),
        Cells::Layer(1e-6),
        Cells::Layer(1e-9),
        Cells::Slivers(1e-3),
        Cells::Slivers(1e-6),
        Cells::Slivers(1e-9),
        Cells::Chevrons(1e-3),
        Cells::Chevrons(1e-6),
        Cells::Chevrons(1e-9),
    ];
    let mut rows = Vec::new();
    for kind in kinds {
        if let Cells::TinyEdges(_) = kind {
            // On matching meshes (no insertion); the non-matching rows below meet the
            // interface insertion's own limit on inserted points.
            let mut matching = Patch::pressed([(2.0, 1.0), (2.0, 1.0)], kind);
            matching.matching = true;
            rows.push(patch_row(
                format!("{}, matching interface, frictionless", kind.describe()),
                &matching,
                size,
            ));
        }
        let patch = Patch::pressed([(2.0, 1.0), (2.0, 1.0)], kind);
        rows.push(patch_row(
            format!("{}, frictionless", kind.describe()),
            &patch,
            size,
        ));
        let mut slip = Patch::pressed([(2.0, 1.0), (2.0, 1.0)], kind);
        let bound = 0.25 * slip.pressure;
        slip.shear = bound;
        slip.offset = [0.01, 0.0];
        slip.law = Arc::new(Tresca::try_new(bound).expect("valid bound"));
        rows.push(patch_row(
            format!("{}, Tresca full slip", kind.describe()),
            &slip,
            size,
        ));
    }
    rows
}

/// The penalty solver at factors 1e0 .. 1e14 on the pressed patch test.
pub fn penalty(size: &Size) -> Vec<Row> {
    let patch = Patch::pressed([(2.0, 1.0), (2.0, 1.0)], Cells::Quads);
    (0..=7)
        .map(|k| {
            let factor = 10f64.powi(2 * k);
            let tolerance = 1.0 / factor + PATCH_TOLERANCE;
            let options =
                Options::new().with("penalty", PenaltyParameter::RelativeToStiffness(factor));
            let outcome = patch.judge(size.patch, "penalty", &options, tolerance);
            Row {
                name: format!("penalty factor {factor:.0e}"),
                expected: format!(
                    "the penalised answer: nodal and resultant errors <= 1/factor + \
                     {PATCH_TOLERANCE:.0e} = {tolerance:.1e}"
                ),
                outcomes: vec![outcome],
            }
        })
        .chain((0..=7).map(|k| {
            let factor = 10f64.powi(2 * k);
            let tolerance = 1.0 / factor + PATCH_TOLERANCE;
            Row {
                name: format!("M1, penalty factor {factor:.0e}"),
                expected: format!(
                    "the condensed solver's answer up to the penalty: relative difference <= \
                     1/factor + {PATCH_TOLERANCE:.0e} = {tolerance:.1e}"
                ),
                outcomes: vec![penalty_m1_outcome(size.manufactured, factor, tolerance)],
            }
        }))
        .collect()
}

/// M1 on non-matching quads (`n` over `3n/2` cells), its contact problem and its exact
/// solution.
fn m1_problem(n: usize, law: Option<Arc<dyn ContactLaw>>) -> Result<ContactProblem, String> {
    let exact = CaseRegistry::builtin()
        .make("M1", Lame::default())
        .map_err(|e| chain(&e))?;
    let meshes = [(BodyId::One, n), (BodyId::Two, n + n / 2)]
        .iter()
        .map(|&(body, cells)| MeshFamily::Quads.generate(&exact.domain(body), cells, 1))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| chain(&e))?;
    let settings = match law {
        Some(law) => ProblemSettings::builder().law(law),
        None => ProblemSettings::builder(),
    }
    .build()
    .map_err(|e| chain(&e))?;
    let problem = DiscreteProblem::try_new(exact, meshes, &settings).map_err(|e| chain(&e))?;
    problem
        .contact_problem()
        .ok_or_else(|| "not a contact case".to_string())
}

fn penalty_m1_outcome(n: usize, factor: f64, tolerance: f64) -> Outcome {
    let reference = match m1_problem(n, None)
        .and_then(|p| solve(&p, SolverRegistry::DEFAULT, &Options::new()))
    {
        Ok(r) => r,
        Err(e) => {
            return Outcome {
                solver: "penalty".to_string(),
                measured: format!("error (reference run): {e}"),
                verdict: Verdict::Refused(e),
            }
        }
    };
    let options = Options::new().with("penalty", PenaltyParameter::RelativeToStiffness(factor));
    let outcome = m1_problem(n, None).and_then(|p| solve(&p, "penalty", &options));
    judge("penalty", outcome, |r| {
        let change = answer_change(&reference, r, 1.0, 1.0);
        (
            format!("relative difference {change:.1e}"),
            change <= tolerance,
        )
    })
}

/// Gaps: pressed at gap 0 and 1e-12, touching at zero load, and open (no contact, the bodies
/// stretched sideways).
pub fn gaps(size: &Size) -> Vec<Row> {
    let base = || Patch::pressed([(2.0, 1.0), (2.0, 1.0)], Cells::Quads);
    let mut rows = Vec::new();
    let pressed = base();
    rows.push(patch_row("gap 0, pressed".to_string(), &pressed, size));
    let mut tiny = base();
    tiny.offset = [0.003, -1e-12];
    rows.push(patch_row("gap 1e-12, pressed".to_string(), &tiny, size));
    let mut touching = base();
    touching.pressure = 0.0;
    touching.lateral = Some(0.0);
    touching.offset = [0.003, 0.0];
    rows.push(patch_row(
        "touching at zero load (forces 0)".to_string(),
        &touching,
        size,
    ));
    let mut open = base();
    open.pressure = 0.0;
    open.lateral = Some(0.01);
    open.opening = 0.01;
    rows.push(patch_row(
        "no contact at all (gap 1e-2, bodies stretched sideways)".to_string(),
        &open,
        size,
    ));
    rows
}

/// Friction bound 0 against frictionless (on M1 and on the pressed patch test), and a huge
/// bound against the tied exact solution (patch test with zero tangential jump).
pub fn friction(size: &Size) -> Vec<Row> {
    let mut rows = Vec::new();
    let outcomes = size
        .solvers
        .iter()
        .map(|solver| bound_zero_outcome(size.manufactured, solver))
        .collect();
    rows.push(Row {
        name: "M1: Tresca g_F = 0 against frictionless".to_string(),
        expected: format!(
            "the same displacements and normal forces (relative difference <= \
             {SAME_PROBLEM_TOLERANCE:.0e}; exact: <= {:.0e}, its certified complementarity), \
             zero friction forces",
            same_problem_tolerance("exact")
        ),
        outcomes,
    });
    let mut zero = Patch::pressed([(2.0, 1.0), (2.0, 1.0)], Cells::Quads);
    zero.law = Arc::new(Tresca::try_new(0.0).expect("valid bound"));
    rows.push(patch_row(
        "patch test, Tresca g_F = 0 (the frictionless exact field)".to_string(),
        &zero,
        size,
    ));
    for bound in [1e3, 1e12] {
        let mut tied = Patch::pressed([(2.0, 1.0), (2.0, 1.0)], Cells::Quads);
        tied.shear = 0.5 * tied.pressure;
        tied.offset = [0.0, 0.0];
        tied.law = Arc::new(Tresca::try_new(bound * tied.pressure).expect("valid bound"));
        rows.push(patch_row(
            format!("patch test, Tresca g_F = {bound:.0e} p: the tied exact field"),
            &tied,
            size,
        ));
    }
    rows
}

fn bound_zero_outcome(n: usize, solver: &str) -> Outcome {
    let run = |law: Arc<dyn ContactLaw>| -> Result<ContactResult, String> {
        solve(&m1_problem(n, Some(law))?, solver, &Options::new())
    };
    let reference = match run(Arc::new(Frictionless)) {
        Ok(r) => r,
        Err(e) => {
            return Outcome {
                solver: solver.to_string(),
                measured: format!("error (frictionless run): {e}"),
                verdict: Verdict::Refused(e),
            }
        }
    };
    let zero = run(Arc::new(Tresca::try_new(0.0).expect("valid bound")));
    judge(solver, zero, |r| {
        let change = answer_change(&reference, r, 1.0, 1.0);
        (
            format!("relative difference {change:.1e}"),
            change <= same_problem_tolerance(solver),
        )
    })
}

// ---------------------------------------------------------------------------------------------
// An exact solution in other units

/// `inner` with lengths multiplied by `length` and moduli by `modulus`: displacement
/// `s u(x/s)`, stress `m sigma(x/s)`, body force `(m/s) f(x/s)`, gap `s h0(x/s)`, friction
/// bound `m g_F`.
struct Scaled {
    inner: Arc<dyn ExactSolution>,
    length: f64,
    modulus: f64,
}

impl Scaled {
    fn back(&self, x: Point) -> Point {
        Point::new(x.x / self.length, x.y / self.length)
    }
}

impl ExactSolution for Scaled {
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn lame(&self) -> Lame {
        let lame = self.inner.lame();
        Lame::try_new(self.modulus * lame.lambda(), self.modulus * lame.mu())
            .expect("positive moduli stay positive")
    }

    fn bodies(&self) -> &'static [BodyId] {
        self.inner.bodies()
    }

    fn domain(&self, body: BodyId) -> Rectangle {
        let r = self.inner.domain(body);
        let s = self.length;
        Rectangle::new(
            Point::new(s * r.min.x, s * r.min.y),
            Point::new(s * r.max.x, s * r.max.y),
        )
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        self.inner.displacement(body, self.back(x)) * self.length
    }

    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        self.inner.gradient(body, self.back(x))
    }

    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        self.inner.body_force(body, self.back(x)) * (self.modulus / self.length)
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        self.inner.dirichlet_sides(body)
    }

    fn neumann_sides(&self, body: BodyId) -> Vec<Side> {
        self.inner.neumann_sides(body)
    }

    fn traction(&self, body: BodyId, side: Side, x: Point) -> Vector {
        self.inner.traction(body, side, self.back(x)) * self.modulus
    }

    fn contact(&self) -> Option<&dyn ExactContact> {
        self.inner.contact().map(|_| self as &dyn ExactContact)
    }
}

impl ExactContact for Scaled {
    fn law(&self) -> Arc<dyn ContactLaw> {
        let inner = self.inner.contact().map_or_else(
            || Arc::new(Frictionless) as Arc<dyn ContactLaw>,
            |c| c.law(),
        );
        Arc::new(ScaledLaw {
            inner,
            length: self.length,
            modulus: self.modulus,
        })
    }

    fn initial_gap(&self, x: f64) -> f64 {
        self.inner
            .contact()
            .map_or(0.0, |c| c.initial_gap(x / self.length))
            * self.length
    }
}

/// A law on a problem whose lengths are scaled by `length` and moduli by `modulus`: the nodes
/// and the state are mapped back to the unscaled problem, the bounds (forces) forward by
/// `length * modulus`.
#[derive(Debug)]
struct ScaledLaw {
    inner: Arc<dyn ContactLaw>,
    length: f64,
    modulus: f64,
}

impl ContactLaw for ScaledLaw {
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn has_friction(&self) -> bool {
        self.inner.has_friction()
    }

    fn friction_bounds(
        &self,
        nodes: &[ContactNode],
        state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError> {
        let (s, m) = (self.length, self.modulus);
        let unscaled: Vec<ContactNode> = nodes
            .iter()
            .map(|n| ContactNode {
                position: Point::new(n.position.x / s, n.position.y / s),
                tributary_measure: n.tributary_measure / s,
                geometric_gap: n.geometric_gap / s,
                initial_gap: n.initial_gap / s,
                ..*n
            })
            .collect();
        let forces = |f: &[f64]| f.iter().map(|x| x / (s * m)).collect::<Vec<f64>>();
        let lengths = |u: &[f64]| u.iter().map(|x| x / s).collect::<Vec<f64>>();
        let bounds = match state {
            None => self.inner.friction_bounds(&unscaled, None)?,
            Some(state) => {
                let (normal, tangential) =
                    (forces(state.normal_forces), forces(state.tangential_forces));
                let (jumps, slips) = (lengths(state.normal_jumps), lengths(state.slips));
                let back = LawState {
                    normal_forces: &normal,
                    tangential_forces: &tangential,
                    normal_jumps: &jumps,
                    slips: &slips,
                };
                self.inner.friction_bounds(&unscaled, Some(&back))?
            }
        };
        Ok(bounds.into_iter().map(|b| b * s * m).collect())
    }

    fn fixed_point(&self) -> Option<vem_contact::FixedPointSettings> {
        self.inner.fixed_point()
    }
}

// ---------------------------------------------------------------------------------------------
// Near-incompressible contact

/// Poisson ratios of the near-incompressible contact rows (each against nu = 0.3).
pub const CONTACT_POISSON_RATIOS: [f64; 3] = [0.49, 0.499, 0.4999];
/// Largest change of the Hertz half-width and peak-pressure errors from nu = 0.3 to a nearly
/// incompressible nu for a locking-free choice (the scene test's bound).
pub const HERTZ_LOCKING_CHANGE: f64 = 0.03;

/// An element of the near-incompressible rows: a registry element, optionally on meshes with
/// every edge's midpoint inserted (what the default chooses on triangles).
struct ElementVariant {
    label: String,
    element: Arc<dyn ElementSpace>,
    midpoints: bool,
}

/// Every registered element, and `vem1-bbar` with edge midpoints on triangles.
fn element_variants(family: &MeshFamily) -> Vec<ElementVariant> {
    let registry = ElementRegistry::builtin();
    let mut variants: Vec<ElementVariant> = registry
        .names()
        .into_iter()
        .map(|name| ElementVariant {
            label: name.to_string(),
            element: registry.make(name).expect("a registered element"),
            midpoints: false,
        })
        .collect();
    if matches!(family, MeshFamily::Triangles) {
        variants.push(ElementVariant {
            label: "vem1-bbar with edge midpoints".to_string(),
            element: registry.make("vem1-bbar").expect("a registered element"),
            midpoints: true,
        });
    }
    variants
}

/// Near-incompressible contact: the two-body divergence-free contact solution E2c on
/// triangles, quadrilaterals and Voronoi cells (non-matching), for every element, at
/// nu = 0.49, 0.499 and 0.4999 against nu = 0.3; and the shipped Hertz scene (the block of
/// quadrilaterals, and of triangles) against plane-strain Hertz with the default element and
/// the elements a user may force.
pub fn incompressible_contact(size: &Size) -> Vec<Row> {
    let mut rows = Vec::new();
    for family in size.locking_families.iter().filter(|f| {
        matches!(
            f,
            MeshFamily::Triangles | MeshFamily::Quads | MeshFamily::Voronoi
        )
    }) {
        for variant in element_variants(family) {
            rows.extend(e2c_locking(&variant, family, size.locking));
        }
    }
    for block in &size.hertz_blocks {
        for element in [None, Some("vem1"), Some("vem1-bbar")] {
            rows.push(hertz_locking(&size.scenes, block, element));
        }
    }
    rows
}

/// E2c errors at each nu of [`CONTACT_POISSON_RATIOS`] against nu = 0.3 with `variant` on
/// `family`, solved by the default contact solver.
fn e2c_locking(variant: &ElementVariant, family: &MeshFamily, n: usize) -> Option<Row> {
    let settings = ProblemSettings::builder()
        .element(Arc::clone(&variant.element))
        .build()
        .expect("valid settings");
    let errors = |nu: f64| -> Result<ErrorNorms, String> {
        let (lambda, mu) = lame_of(nu);
        let lame = Lame::try_new(lambda, mu).map_err(|e| chain(&e))?;
        let exact: Arc<dyn ExactSolution> =
            Arc::new(crate::exact::DivergenceFreeContact::new(lame));
        let mut meshes = Vec::new();
        for (body, seed) in [(BodyId::One, 1), (BodyId::Two, 2)] {
            let mesh = family
                .generate(&exact.domain(body), n, seed)
                .map_err(|e| chain(&e))?;
            meshes.push(if variant.midpoints {
                mesh.with_edge_midpoints().map_err(|e| chain(&e))?
            } else {
                mesh
            });
        }
        let problem = DiscreteProblem::try_new(Arc::clone(&exact), meshes, &settings)
            .map_err(|e| chain(&e))?;
        let mut solver = SolverRegistry::builtin()
            .make(SolverRegistry::DEFAULT, &Options::new())
            .map_err(|e| chain(&e))?;
        let solution = problem.solve(&mut *solver).map_err(|e| chain(&e))?;
        let parts = solution.errors(&*exact).map_err(|e| chain(&e))?;
        Ok(ErrorNorms::combine(&parts))
    };
    let name = format!(
        "{}: E2c contact on {}, nu = 0.3 .. {}",
        variant.label,
        family.name(),
        CONTACT_POISSON_RATIOS[CONTACT_POISSON_RATIOS.len() - 1]
    );
    let solver = format!("contact ({})", SolverRegistry::DEFAULT);
    locking_row(name, solver, &CONTACT_POISSON_RATIOS, |nu| {
        errors(nu).map(|e| (e.relative_grad(), e.relative_l2()))
    })
}

/// The Hertz scene `hertz.toml` of `scenes` with `block` as the block's mesh file, Poisson's
/// ratio `nu` on both bodies and `element` forced on both (the default choice when `None`):
/// the relative errors of the half-width and the peak pressure against plane-strain Hertz, and
/// the warnings.
fn hertz_errors(
    scenes: &Path,
    block: &str,
    nu: f64,
    element: Option<&str>,
) -> Result<((f64, f64), Vec<String>), String> {
    use vem_scene::{BuildOptions, Model};
    let text = std::fs::read_to_string(scenes.join("hertz.toml"))
        .map_err(|e| format!("hertz.toml: {e}"))?
        .replace("hertz_block.msh", block)
        .replace("nu = 0.3,", &format!("nu = {nu},"));
    let text = match element {
        Some(element) => text.replace(
            "mesh = { file",
            &format!("element = \"{element}\"\nmesh = {{ file"),
        ),
        None => text,
    };
    let (scene, _) = vem_scene::toml_file::parse(&text).map_err(|e| e.message)?;
    let options = BuildOptions {
        base: scenes.to_path_buf(),
        ..BuildOptions::default()
    };
    let model = Model::build(&scene, &options).map_err(|e| e.to_string())?;
    let outcome = model.solve().map_err(|e| e.to_string())?;
    let mut warnings: Vec<String> = outcome
        .summary
        .bodies
        .iter()
        .flat_map(|b| b.warnings.iter().cloned())
        .collect();
    let contact = outcome
        .summary
        .contact
        .as_ref()
        .ok_or("the Hertz scene has contact")?;
    warnings.extend(contact.warnings.iter().map(|w| w.to_string()));
    let hertz = contact.hertz.first().ok_or("the Hertz scene compares")?;
    Ok((
        (hertz.half_width_error(), hertz.peak_pressure_error()),
        warnings,
    ))
}

/// The Hertz scene with the block `block` and `element` (the default choice when `None`): the
/// change of the half-width and peak-pressure errors from nu = 0.3 to each nu of
/// [`CONTACT_POISSON_RATIOS`].
fn hertz_locking(scenes: &Path, block: &str, element: Option<&str>) -> Row {
    let label = element.unwrap_or("default element");
    let name = format!("{label}: Hertz scene, block {block}, nu = 0.3 .. 0.4999");
    let expected = format!(
        "errors of a and p0 within {:.0} % of those at nu = 0.3",
        100.0 * HERTZ_LOCKING_CHANGE
    );
    let solver = format!("contact ({})", SolverRegistry::DEFAULT);
    let refused = |error: String| {
        one_outcome(
            name.clone(),
            expected.clone(),
            solver.clone(),
            format!("error: {error}"),
            Verdict::Refused(error),
        )
    };
    let ((a_0, p_0), _) = match hertz_errors(scenes, block, 0.3, element) {
        Ok(r) => r,
        Err(error) => return refused(error),
    };
    let mut measured = vec![format!(
        "a {:+.1} %, p0 {:+.1} % at 0.3",
        100.0 * a_0,
        100.0 * p_0
    )];
    let (mut worst, mut warned) = (0.0_f64, Vec::new());
    for &nu in &CONTACT_POISSON_RATIOS {
        match hertz_errors(scenes, block, nu, element) {
            Ok(((a, p), warnings)) => {
                worst = worst.max((a - a_0).abs()).max((p - p_0).abs());
                measured.push(format!(
                    "{nu}: a {:+.1} %, p0 {:+.1} %",
                    100.0 * a,
                    100.0 * p
                ));
                warned.extend(warnings);
            }
            Err(error) => return refused(format!("nu = {nu}: {error}")),
        }
    }
    let verdict = if worst <= HERTZ_LOCKING_CHANGE {
        Verdict::Pass
    } else if let Some(warning) = warned.first() {
        Verdict::Warned(warning.clone())
    } else {
        Verdict::Wrong
    };
    one_outcome(name, expected, solver, measured.join("; "), verdict)
}
