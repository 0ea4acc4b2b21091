//! The consistent pressure and friction traction: reconstructions of nodal contact forces
//! compared on the cases where the plain L2 projection dips below zero or crosses the friction
//! bound (docs/contact.md, section 5.1; docs/hertz.md, section 2). Run with
//!
//! ```text
//! cargo run --release -p vem-integration-tests --example pressure_reconstruction [-- --large] [--verbose]
//! ```
//!
//! Cases: the Hertz scene (`crates/vem-cli/scenes/hertz.toml`: a half-disc on a block,
//! non-matching Gmsh meshes, h_c = 0.01) and the meshes of `cargo xtask hertz` (h_c = 0.08,
//! 0.04, 0.02),
//! against Hertz's peak and profile (and the reconstructions of Hertz's own profile from its
//! consistent forces on the same support, no solve: what the reconstruction alone costs); a rigid cylinder (R = 1) on a Voronoi block
//! `[-1, 1] x [-1, 0]` (seed 1, bottom pushed up by 0.01) at n = 60, five nodes in contact, and
//! with `--large` at n = 300 (174 508 unknowns); an elastic flat punch on a block and a rigid
//! flat punch (chamfered edges) in a block (n = 40, 80), with Coulomb friction F = 0.3, pressed
//! and sheared to slip at the edges; the Tresca scene
//! (`crates/vem-cli/scenes/tresca.toml`). For each, the smallest reconstructed pressure over
//! the peak and the largest friction traction against the same reconstruction of its bound,
//! for
//!
//! * `l2`: the plain L2 projection (`TractionBound::Unbounded`), the former definition;
//! * `lumped`: the row-sum (lumped) projection `p_k = r_k / int phi_k`, equal to the nodal
//!   coefficients of Wohlmuth's dual (biorthogonal) basis;
//! * `fct`: flux-corrected transport, the L2 projection limited towards the lumped one by
//!   Zalesak's limiter (bounds: the lumped values of the neighbours);
//! * `bounded`: the L2 projection onto the functions within the bound with the forces'
//!   resultant (`NonNegative`, `Magnitude`), the library's `consistent_pressure` and
//!   `consistent_friction_traction`;
//!
//! and how each reproduces a linear traction from consistent forces (the largest nodal error
//! relative to the traction's maximum, on the uneven polyline of the tests). `--verbose` prints
//! the profiles at h_c = 0.02.

use std::error::Error;
use std::path::Path;
use std::sync::Arc;

use vem_contact::{
    consistent_traction, CondensedSolver, ContactProblem, ContactResult, Coulomb, Frictionless,
    InterfaceNode, Obstacle, TractionBound, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{hexagons, structured_quads, voronoi, Rectangle};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::io::read_gmsh;
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;
use vem_verify::exact::HertzContact;

type Res<T> = Result<T, Box<dyn Error>>;

/// One interface as the reconstructions see it.
struct Interface {
    positions: Vec<Point>,
    lengths: Vec<f64>,
    normal_forces: Vec<f64>,
    friction_forces: Vec<f64>,
    bounds: Option<Vec<f64>>,
    support: Vec<bool>,
}

impl Interface {
    /// The nodes of `result` (one pair); `original` the vertex counts of the bodies before
    /// insertion; `bounds` the nodal friction bounds, if any.
    fn of(result: &ContactResult, original: &[usize], bounds: Option<Vec<f64>>) -> Self {
        let nodes = &result.nodes;
        let flags = |f: &dyn Fn(&InterfaceNode) -> bool| nodes.iter().map(f).collect::<Vec<_>>();
        let support = if nodes.iter().any(|n| n.body_b.is_none()) {
            vec![true; nodes.len()]
        } else {
            let a = flags(&|n| n.vertex_a < original[n.body_a]);
            let b = flags(&|n| {
                n.body_b
                    .zip(n.vertex_b)
                    .is_some_and(|(b, v)| v < original[b])
            });
            let count = |v: &[bool]| v.iter().filter(|&&x| x).count();
            if count(&a) < count(&b) {
                a
            } else {
                b
            }
        };
        Self {
            positions: nodes.iter().map(|n| n.position).collect(),
            lengths: nodes.iter().map(|n| n.tributary_measure).collect(),
            normal_forces: nodes.iter().map(|n| n.normal_force).collect(),
            friction_forces: nodes.iter().map(|n| n.friction_t()).collect(),
            bounds,
            support,
        }
    }
}

/// Arc lengths, the support nodes and the hat data of a polyline.
struct Hats {
    /// For each node: its support interval and coordinate in it.
    location: Vec<(usize, f64)>,
    lengths: Vec<f64>,
}

impl Hats {
    fn new(positions: &[Point], support: &[bool]) -> Self {
        let mut arc = vec![0.0];
        for w in positions.windows(2) {
            arc.push(arc.last().unwrap() + (w[1] - w[0]).norm());
        }
        let n = positions.len();
        let mut nodes: Vec<usize> = Vec::new();
        for i in 0..n {
            let marked = support[i] || i == 0 || i + 1 == n;
            if marked && nodes.last().is_none_or(|&k| arc[i] > arc[k]) {
                nodes.push(i);
            } else if i + 1 == n && nodes.len() > 1 {
                let last = nodes.len() - 1;
                nodes[last] = i;
            }
        }
        let lengths: Vec<f64> = nodes.windows(2).map(|w| arc[w[1]] - arc[w[0]]).collect();
        let mut k = 0;
        let location = arc
            .iter()
            .map(|&s| {
                while k + 2 < nodes.len() && s > arc[nodes[k + 1]] {
                    k += 1;
                }
                (k, ((s - arc[nodes[k]]) / lengths[k]).clamp(0.0, 1.0))
            })
            .collect();
        Self { location, lengths }
    }

    fn m(&self) -> usize {
        self.lengths.len() + 1
    }

    fn rhs(&self, forces: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; self.m()];
        for (&(k, t), f) in self.location.iter().zip(forces) {
            r[k] += (1.0 - t) * f;
            r[k + 1] += t * f;
        }
        r
    }

    fn lumped_mass(&self) -> Vec<f64> {
        (0..self.m())
            .map(|k| {
                0.5 * (if k > 0 { self.lengths[k - 1] } else { 0.0 }
                    + self.lengths.get(k).copied().unwrap_or(0.0))
            })
            .collect()
    }

    fn values(&self, c: &[f64]) -> Vec<f64> {
        self.location
            .iter()
            .map(|&(k, t)| (1.0 - t) * c[k] + t * c[k + 1])
            .collect()
    }

    /// The row-sum projection.
    fn lumped(&self, forces: &[f64]) -> Vec<f64> {
        let r = self.rhs(forces);
        let c: Vec<f64> = r
            .iter()
            .zip(self.lumped_mass())
            .map(|(r, m)| r / m)
            .collect();
        self.values(&c)
    }

    /// The L2 projection limited towards the lumped one (Zalesak's FCT limiter on the
    /// antidiffusive fluxes `f_kl = M_kl (c_k - c_l)` of the consistent mass matrix, bounds
    /// from the lumped values of the neighbours).
    fn fct(&self, forces: &[f64], l2_coefficients: &[f64]) -> Vec<f64> {
        let m = self.m();
        let mass = self.lumped_mass();
        let r = self.rhs(forces);
        let low: Vec<f64> = r.iter().zip(&mass).map(|(r, m)| r / m).collect();
        let high = l2_coefficients;
        let flux = |k: usize, l: usize| {
            let off = self.lengths[k.min(l)] / 6.0;
            off * (high[k] - high[l])
        };
        let neighbours = |k: usize| {
            let mut v = vec![];
            if k > 0 {
                v.push(k - 1);
            }
            if k + 1 < m {
                v.push(k + 1);
            }
            v
        };
        let mut plus = vec![1.0; m];
        let mut minus = vec![1.0; m];
        for k in 0..m {
            let (mut p_pos, mut p_neg) = (0.0, 0.0);
            let (mut max, mut min) = (low[k], low[k]);
            for l in neighbours(k) {
                let f = flux(k, l);
                if f > 0.0 {
                    p_pos += f;
                } else {
                    p_neg += f;
                }
                max = max.max(low[l]);
                min = min.min(low[l]);
            }
            let q_pos = mass[k] * (max - low[k]);
            let q_neg = mass[k] * (min - low[k]);
            plus[k] = if p_pos > 0.0 {
                (q_pos / p_pos).min(1.0)
            } else {
                1.0
            };
            minus[k] = if p_neg < 0.0 {
                (q_neg / p_neg).min(1.0)
            } else {
                1.0
            };
        }
        let c: Vec<f64> = (0..m)
            .map(|k| {
                let correction: f64 = neighbours(k)
                    .into_iter()
                    .map(|l| {
                        let f = flux(k, l);
                        let alpha = if f > 0.0 {
                            plus[k].min(minus[l])
                        } else {
                            minus[k].min(plus[l])
                        };
                        alpha * f
                    })
                    .sum();
                low[k] + correction / mass[k]
            })
            .collect();
        self.values(&c)
    }

    /// The support coefficients of the plain L2 projection, read back from its nodal values
    /// at the support nodes (the values are linear in between).
    fn coefficients_of(&self, values: &[f64]) -> Vec<f64> {
        let mut c = vec![f64::NAN; self.m()];
        for (&(k, t), v) in self.location.iter().zip(values) {
            if t == 0.0 {
                c[k] = *v;
            } else if t == 1.0 {
                c[k + 1] = *v;
            }
        }
        c
    }
}

/// The four reconstructions of one set of forces (and, for friction, of the bounds).
struct Reconstructions {
    l2: Vec<f64>,
    lumped: Vec<f64>,
    fct: Vec<f64>,
    bounded: Vec<f64>,
}

fn reconstruct(i: &Interface, forces: &[f64], bound: TractionBound<'_>) -> Reconstructions {
    let hats = Hats::new(&i.positions, &i.support);
    let project = |b| consistent_traction(&i.positions, forces, &i.support, &i.lengths, b);
    let l2 = project(TractionBound::Unbounded);
    let fct = hats.fct(forces, &hats.coefficients_of(&l2));
    Reconstructions {
        lumped: hats.lumped(forces),
        fct,
        bounded: project(bound),
        l2,
    }
}

fn min_over_peak(p: &[f64]) -> f64 {
    let peak = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    p.iter().copied().fold(f64::INFINITY, f64::min) / peak
}

/// Prints min/peak of each pressure reconstruction; with friction, the largest `|t| / beta`
/// where `beta` is the same reconstruction of the bounds (`> 1`: the picture crosses the
/// bound).
fn report(name: &str, interface: &Interface) {
    let p = reconstruct(
        interface,
        &interface.normal_forces,
        TractionBound::NonNegative,
    );
    println!(
        "{name}: min / peak of the pressure: l2 {:+.2}%, lumped {:+.2}%, fct {:+.2}%, bounded {:+.2}%",
        100.0 * min_over_peak(&p.l2),
        100.0 * min_over_peak(&p.lumped),
        100.0 * min_over_peak(&p.fct),
        100.0 * min_over_peak(&p.bounded),
    );
    if let Some(bounds) = &interface.bounds {
        let t = reconstruct(
            interface,
            &interface.friction_forces,
            TractionBound::Magnitude(bounds),
        );
        let beta = reconstruct(interface, bounds, TractionBound::NonNegative);
        let worst = |t: &[f64], beta: &[f64]| {
            t.iter()
                .zip(beta)
                .map(|(t, b)| t.abs() - b)
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let scale = beta.l2.iter().copied().fold(0.0, f64::max);
        let nodal = interface
            .friction_forces
            .iter()
            .zip(bounds)
            .map(|(t, b)| t.abs() - b)
            .fold(f64::NEG_INFINITY, f64::max);
        let at = |t: &[f64], beta: &[f64]| {
            let k = (0..t.len())
                .max_by(|&a, &b| (t[a].abs() - beta[a]).total_cmp(&(t[b].abs() - beta[b])))
                .unwrap();
            format!("{:.3} vs {:.3}", t[k], beta[k])
        };
        println!(
            "{name}: max (|t| - bound) / max bound: l2 {:+.2}% ({}), lumped {:+.2}%, fct {:+.2}%, \
             bounded {:+.2}% ({}); nodal forces {:+.1e} of the largest bound force",
            100.0 * worst(&t.l2, &beta.l2) / scale,
            at(&t.l2, &beta.l2),
            100.0 * worst(&t.lumped, &beta.lumped) / scale,
            100.0 * worst(&t.fct, &beta.fct) / scale,
            100.0 * worst(&t.bounded, &beta.bounded) / scale,
            at(&t.bounded, &beta.bounded),
            nodal / bounds.iter().copied().fold(0.0, f64::max),
        );
    }
}

fn material(young: f64) -> Res<Material> {
    Ok(Material::from_young_poisson(young, 0.3, Plane::Strain)?)
}

/// The Hertz half-disc on the block of the meshes `disc`, `block` (relative to the workspace);
/// also compares the peak and the profile with Hertz's.
fn hertz(name: &str, disc: &str, block: &str, verbose: bool) -> Res<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let disc = read_gmsh(root.join(disc))?;
    let block = read_gmsh(root.join(block))?;
    let original = [disc.n_vertices(), block.n_vertices()];
    let element = Arc::new(LowestOrderVem::default());
    let disc = ElasticBody::builder("disc", disc, material(100.0)?, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.0, -0.02)
        }))
        .build()?;
    let block = ElasticBody::builder("block", block, material(100.0)?, element)
        .clamp("bottom")
        .build()?;
    let result = ContactProblem::two_bodies(disc, "arc", block, "top", Frictionless)
        .with_interface_options(InterfaceOptions::builder().max_distance(0.05).build()?)
        .solve(&mut CondensedSolver::default())?;
    let interface = Interface::of(&result, &original, None);
    report(name, &interface);
    let load = result.force_on_body_a().y;
    let e_star = HertzContact::plane_strain_modulus(100.0, 0.3, 100.0, 0.3);
    let exact = HertzContact::try_new(1.0, e_star, load)?;
    let p = reconstruct(
        &interface,
        &interface.normal_forces,
        TractionBound::NonNegative,
    );
    let (a, p0) = (exact.half_width(), exact.peak_pressure());
    let figures = |values: &[f64]| {
        let peak = values.iter().copied().fold(0.0, f64::max) / p0 - 1.0;
        let profile = result
            .nodes
            .iter()
            .zip(values)
            .filter(|(n, _)| n.position.x.abs() <= 0.8 * a)
            .map(|(n, v)| (v / exact.pressure(n.position.x) - 1.0).abs())
            .fold(0.0, f64::max);
        format!(
            "peak {:+.2}%, profile {:.2}%",
            100.0 * peak,
            100.0 * profile
        )
    };
    if verbose {
        println!("x/a, raw/p0, l2/p0, lumped/p0, bounded/p0, hertz/p0, support");
        for (i, n) in result.nodes.iter().enumerate() {
            let x = n.position.x;
            if x.abs() < 1.5 * a {
                println!(
                    "{:+.3} {:.4} {:+.4} {:.4} {:.4} {:.4} {}",
                    x / a,
                    n.pressure / p0,
                    p.l2[i] / p0,
                    p.lumped[i] / p0,
                    p.bounded[i] / p0,
                    exact.pressure(x) / p0,
                    interface.support[i]
                );
            }
        }
    }
    println!(
        "{name} against Hertz: l2 {}; lumped {}; fct {}; bounded {}",
        figures(&p.l2),
        figures(&p.lumped),
        figures(&p.fct),
        figures(&p.bounded)
    );
    // What the reconstruction alone costs: Hertz's own profile, its consistent forces on the
    // support's hats (no solve), reconstructed the same ways.
    let own = own_forces(&interface, |x| exact.pressure(x));
    let q = reconstruct(&interface, &own, TractionBound::NonNegative);
    println!(
        "{name}, Hertz's own profile on the same support: l2 {}; lumped {}; bounded {}",
        figures(&q.l2),
        figures(&q.lumped),
        figures(&q.bounded)
    );
    Ok(())
}

/// The consistent nodal forces `int p phi_k` of a pressure `p(x)` on the hats of the support
/// nodes (ordered by x), zero on the other nodes: a reconstruction onto those hats that is
/// exact returns `p` at the support nodes.
fn own_forces(interface: &Interface, p: impl Fn(f64) -> f64) -> Vec<f64> {
    let mut support: Vec<usize> = (0..interface.positions.len())
        .filter(|&i| interface.support[i])
        .collect();
    support.sort_by(|&a, &b| {
        interface.positions[a]
            .x
            .total_cmp(&interface.positions[b].x)
    });
    let mut forces = vec![0.0; interface.positions.len()];
    const POINTS: usize = 2000;
    for pair in support.windows(2) {
        let (x0, x1) = (
            interface.positions[pair[0]].x,
            interface.positions[pair[1]].x,
        );
        let h = (x1 - x0) / POINTS as f64;
        for k in 0..POINTS {
            // Midpoint rule: the square-root end of the zone is integrable, the rule converges.
            let t = (k as f64 + 0.5) / POINTS as f64;
            let w = p(x0 + t * (x1 - x0)) * h;
            forces[pair[0]] += (1.0 - t) * w;
            forces[pair[1]] += t * w;
        }
    }
    forces
}

/// A rigid cylinder (R = 1, touching at the origin) on a Voronoi block `[-1, 1] x [-1, 0]` of
/// size `n` whose bottom is moved up by `lift`.
fn cylinder(n: usize, lift: f64) -> Res<()> {
    let block = voronoi(
        &Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0)),
        n,
        1,
    )?;
    let element = Arc::new(LowestOrderVem::default());
    let body = ElasticBody::builder("block", block, material(100.0)?, element)
        .dirichlet(Dirichlet::prescribed("bottom", Component::All, move |_| {
            Vector::new(0.0, lift)
        }))
        .build()?;
    let cylinder = Obstacle::Circle {
        centre: Point::new(0.0, 1.0),
        radius: 1.0,
    };
    let result = ContactProblem::against_obstacle(body, "top", cylinder, Frictionless)
        .solve(&mut CondensedSolver::default())?;
    let counts = result.status_counts();
    println!(
        "cylinder on voronoi n = {n}: {} unknowns, {} nodes in contact",
        result.model.bodies[0].free_dofs,
        counts.active()
    );
    report(
        &format!("cylinder n = {n}"),
        &Interface::of(&result, &[0], None),
    );
    Ok(())
}

/// An elastic flat punch `[-0.25, 0.25] x [0, 0.25]` (hexagons) pressed and sheared on a block
/// `[-1, 1] x [-1, 0]` (quads), Coulomb F = 0.3.
fn punch() -> Res<()> {
    let element = Arc::new(LowestOrderVem::default());
    let punch_mesh = hexagons(
        &Rectangle::new(Point::new(-0.25, 0.0), Point::new(0.25, 0.25)),
        12,
    )?;
    let block_mesh = structured_quads(
        &Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0)),
        40,
        20,
    )?;
    let original = [punch_mesh.n_vertices(), block_mesh.n_vertices()];
    let punch = ElasticBody::builder("punch", punch_mesh, material(100.0)?, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.002, -0.01)
        }))
        .build()?;
    let block = ElasticBody::builder("block", block_mesh, material(100.0)?, element)
        .clamp("bottom")
        .build()?;
    let result = ContactProblem::two_bodies(punch, "bottom", block, "top", Coulomb::try_new(0.3)?)
        .solve(&mut CondensedSolver::default())?;
    let bounds = result
        .fixed_point
        .as_ref()
        .map(|f| f.final_bounds.clone())
        .ok_or("Coulomb iterates")?;
    let counts = result.status_counts();
    println!(
        "coulomb punch: {} stick, {} slip, {} open",
        counts.stick, counts.slip, counts.open
    );
    report(
        "coulomb punch",
        &Interface::of(&result, &original, Some(bounds)),
    );
    Ok(())
}

/// A rigid flat punch (`[-0.25, 0.25]`, chamfered edges rising by 0.1 over 0.25) pressed
/// into a block `[-1, 1] x [-1, 0]` (quads, `n` across) and sheared: the block's bottom moves
/// by `(0.004, 0.01)`, Coulomb F = 0.3.
fn rigid_punch(n: usize) -> Res<()> {
    let block_mesh = structured_quads(
        &Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0)),
        n,
        n / 2,
    )?;
    let element = Arc::new(LowestOrderVem::default());
    let block = ElasticBody::builder("block", block_mesh, material(100.0)?, element)
        .dirichlet(Dirichlet::prescribed("bottom", Component::All, |_| {
            Vector::new(0.004, 0.01)
        }))
        .build()?;
    let punch = Obstacle::Polyline(vec![
        Point::new(0.5, 0.1),
        Point::new(0.25, 0.0),
        Point::new(-0.25, 0.0),
        Point::new(-0.5, 0.1),
    ]);
    let result = ContactProblem::against_obstacle(block, "top", punch, Coulomb::try_new(0.3)?)
        .solve(&mut CondensedSolver::default())?;
    let bounds = result
        .fixed_point
        .as_ref()
        .map(|f| f.final_bounds.clone())
        .ok_or("Coulomb iterates")?;
    let counts = result.status_counts();
    println!(
        "rigid punch n = {n}: {} stick, {} slip, {} open",
        counts.stick, counts.slip, counts.open
    );
    report(
        &format!("rigid punch n = {n}"),
        &Interface::of(&result, &[0], Some(bounds)),
    );
    Ok(())
}

/// The Tresca scene (`crates/vem-cli/scenes/tresca.toml`).
fn tresca() -> Res<()> {
    let element = Arc::new(LowestOrderVem::default());
    let block_mesh = hexagons(
        &Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 0.25)),
        16,
    )?;
    let foundation_mesh = vem_mesh::generators::MeshFamily::Quads.generate(
        &Rectangle::new(Point::new(-0.25, -0.5), Point::new(1.25, 0.0)),
        18,
        1,
    )?;
    let original = [block_mesh.n_vertices(), foundation_mesh.n_vertices()];
    let block = ElasticBody::builder("block", block_mesh, material(10.0)?, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::X, |_| {
            Vector::new(0.02, 0.0)
        }))
        .traction("top", |_| Vector::new(0.0, -0.2))
        .build()?;
    let foundation = ElasticBody::builder("foundation", foundation_mesh, material(10.0)?, element)
        .clamp("bottom")
        .build()?;
    let law = Tresca::try_new(0.1)?;
    let result = ContactProblem::two_bodies(block, "bottom", foundation, "top", law)
        .solve(&mut CondensedSolver::default())?;
    let bounds: Vec<f64> = result
        .nodes
        .iter()
        .map(|n| 0.1 * n.tributary_measure)
        .collect();
    report(
        "tresca scene",
        &Interface::of(&result, &original, Some(bounds)),
    );
    Ok(())
}

/// The largest nodal error of each reconstruction of a linear traction (consistent forces)
/// on an uneven polyline with a coarse support, relative to the traction's maximum.
fn linear() {
    let s = [
        0.0, 0.1, 0.1007, 0.23, 0.31, 0.3102, 0.45, 0.6, 0.62, 0.8, 1.0,
    ];
    let positions: Vec<Point> = s.iter().map(|&s| Point::new(s, 0.0)).collect();
    let exact: Vec<f64> = s.iter().map(|s| 2.0 - 1.5 * s).collect();
    let mut forces = vec![0.0; s.len()];
    for k in 0..s.len() - 1 {
        let l = s[k + 1] - s[k];
        forces[k] += l * (2.0 * exact[k] + exact[k + 1]) / 6.0;
        forces[k + 1] += l * (exact[k] + 2.0 * exact[k + 1]) / 6.0;
    }
    let lengths: Vec<f64> = (0..s.len())
        .map(|i| {
            0.5 * (if i > 0 { s[i] - s[i - 1] } else { 0.0 }
                + if i + 1 < s.len() {
                    s[i + 1] - s[i]
                } else {
                    0.0
                })
        })
        .collect();
    let support: Vec<bool> = (0..s.len()).map(|i| i % 3 == 0).collect();
    let interface = Interface {
        positions,
        lengths,
        normal_forces: forces.clone(),
        friction_forces: vec![],
        bounds: None,
        support,
    };
    let p = reconstruct(&interface, &forces, TractionBound::NonNegative);
    let error = |v: &[f64]| {
        v.iter()
            .zip(&exact)
            .map(|(v, e)| (v - e).abs())
            .fold(0.0, f64::max)
            / 2.0
    };
    println!(
        "linear traction 2 - 1.5 s, largest error / max: l2 {:.1e}, lumped {:.1e}, fct {:.1e}, bounded {:.1e}",
        error(&p.l2),
        error(&p.lumped),
        error(&p.fct),
        error(&p.bounded)
    );
}

/// How far the cylinder cases push the block's bottom up: 5 nodes in contact at n = 60.
const LIFT: f64 = 0.01;

fn main() -> Res<()> {
    let large = std::env::args().any(|a| a == "--large");
    linear();
    let verbose = std::env::args().any(|a| a == "--verbose");
    hertz(
        "hertz scene",
        "crates/vem-cli/scenes/hertz_disc.msh",
        "crates/vem-cli/scenes/hertz_block.msh",
        verbose,
    )?;
    // The scene's meshes are those of h_c = 0.01.
    for h in ["0.08", "0.04", "0.02"] {
        hertz(
            &format!("hertz h_c = {h}"),
            &format!("xtask/data/hertz/disc_hc{h}.msh"),
            &format!("xtask/data/hertz/block_hc{h}.msh"),
            verbose && h == "0.02",
        )?;
    }
    cylinder(60, LIFT)?;
    if large {
        cylinder(300, LIFT)?;
    }
    punch()?;
    rigid_punch(40)?;
    rigid_punch(80)?;
    tresca()?;
    Ok(())
}
