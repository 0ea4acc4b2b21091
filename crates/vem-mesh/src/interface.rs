//! Interface node insertion: makes two facing boundary parts node-to-node.
//!
//! The lowest-order VEM accepts any number of vertices per polygon, so two meshes that do not
//! match on the contact interface Gamma_C are made to match by inserting every node of one side
//! into the other side's boundary edges, and vice versa (spec section 2, "Non-matching
//! interfaces"). Polygons gain collinear vertices, nothing else changes, and the contact
//! constraint `[u]_nu <= h0` becomes one inequality per node pair.
//!
//! # Conventions
//!
//! - Side **a** is body 1, side **b** is body 2 of the spec. Each part is ordered into a chain
//!   in the direction of its body's counter-clockwise boundary (the body lies to the left), so
//!   two facing chains run in opposite directions.
//! - The nodal normal of a chain node is the normalised mean of the outward unit normals of
//!   its one or two chain edges. The pair normal [`InterfacePair::normal`] is the nodal normal
//!   of body a at `node_a` (nu_1 of the spec; nu_2 = -nu_1).
//! - Nodes of a are projected onto b along their nodal normals (a ray cast in both directions
//!   against b's polyline, nearest crossing). Nodes of b are projected onto a along a's normal
//!   field interpolated linearly between nodal normals: the point x(s) on edge (p, q) such that
//!   x_b - x(s) is parallel to (1 - s) n_p + s n_q. On a straight part of a this is the closest
//!   point; on a polygon inscribed in a circle it is the radial projection; it is always the
//!   inverse of the ray cast, so the two projections order consistently along the chains.
//! - `initial_gap = (x_b - x_a) . normal`: positive when the bodies are apart. The discrete
//!   contact condition at a pair is `[u]_nu = (u_a - u_b) . normal <= initial_gap` (plus any
//!   user-given h0).
//! - `tributary_length` is half the summed lengths of the paired edges of side a next to the
//!   node (the lengths of the trapezoidal rule on the paired range); over all pairs it sums to
//!   the paired length of side a.
//! - Pairs are ordered along side a's chain.
//!
//! # Snapping
//!
//! A projected point closer to an existing node than `max(snap_tolerance, min_edge_fraction)`
//! times the length of the edge it falls on is not inserted: the existing node is used instead
//! (coincident and nearly coincident nodes pair with each other, and no edge shorter than that
//! fraction is created, which protects the mesh assumption A1). The tangential misfit this
//! introduces is at most that fraction of the edge length.
//!
//! That misfit is removed where it can be without changing the bodies' shapes
//! ([`InterfaceOptions::align_snapped_nodes`], on by default): when a snapped pair joins two
//! existing nodes that do not coincide, the node of side b moves onto the projection of side
//! a's node (the point a's node's ray hits on b) if b's chain is straight at that node (its two
//! chain edges collinear, the node not an end of the chain); otherwise side a's node moves onto
//! the projection of b's node if a's chain is straight there. The node moves along its own
//! straight chain by at most the snapping fraction of an adjacent edge, so the body's domain is
//! unchanged and both sides share exactly the same interface points: a linear field is then
//! represented without any misfit (contact patch tests exact to round-off). Only where both
//! chains bend at the pair (two curved parts), or at an end of a chain, does the misfit of the
//! snapping remain.
//!
//! # Different extents
//!
//! Only the range where the parts overlap is paired: nodes whose projection misses the other
//! part (beyond its ends, or farther than [`InterfaceOptions::max_distance`]) are not
//! interface nodes. Each end of the overlap is an end node of one part, paired with a node of
//! the other part or with a point inserted into it.
//!
//! ```
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::interface::{insert_interface_nodes, InterfaceOptions};
//! use vem_mesh::Point;
//! // Body 1 above body 2, sharing y = 0, with 2 and 3 cells along the interface.
//! let body_1 = structured_quads(&Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0)), 2, 2)?;
//! let body_2 = structured_quads(&Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)), 3, 3)?;
//! let interface =
//!     insert_interface_nodes(&body_1, "bottom", &body_2, "top", &InterfaceOptions::default())?;
//! // Positions 0, 1/3, 1/2, 2/3, 1: two inserted into body 1, one into body 2.
//! assert_eq!(interface.pairs.len(), 5);
//! assert_eq!((interface.inserted_a, interface.inserted_b), (2, 1));
//! let length: f64 = interface.pairs.iter().map(|p| p.tributary_length).sum();
//! assert!((length - 1.0).abs() < 1e-14);
//! assert!(interface.pairs.iter().all(|p| p.initial_gap.abs() < 1e-15 && p.normal.y == -1.0));
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

use std::collections::{HashMap, HashSet};

use crate::{geometry, Mesh, MeshError, PartSpec, Point, Vector};

/// Tolerance (relative to an edge's length) for a ray that crosses a chain exactly at an
/// interior vertex, where rounding may put the crossing just outside both edges.
const VERTEX_CROSSING: f64 = 1e-12;

/// Settings of [`insert_interface_nodes`]; build them with [`InterfaceOptions::builder`]
/// (every value is checked there) or take the [`Default`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceOptions {
    snap_tolerance: f64,
    min_edge_fraction: f64,
    max_distance: Option<f64>,
    align_snapped_nodes: bool,
}

impl Default for InterfaceOptions {
    /// `snap_tolerance = 1e-6`, `min_edge_fraction = 1e-3`, no `max_distance`,
    /// `align_snapped_nodes = true`.
    fn default() -> Self {
        Self {
            snap_tolerance: 1e-6,
            min_edge_fraction: 1e-3,
            max_distance: None,
            align_snapped_nodes: true,
        }
    }
}

impl InterfaceOptions {
    /// A builder starting from the defaults.
    ///
    /// ```
    /// use vem_mesh::{interface::InterfaceOptions, MeshError};
    /// let near = InterfaceOptions::builder().max_distance(0.05).build()?;
    /// assert_eq!(near.max_distance(), Some(0.05));
    /// match InterfaceOptions::builder().max_distance(-1.0).build() {
    ///     Err(MeshError::InvalidOption { setting, .. }) => assert_eq!(setting, "max_distance"),
    ///     other => panic!("{other:?}"),
    /// }
    /// # Ok::<(), MeshError>(())
    /// ```
    pub fn builder() -> InterfaceOptionsBuilder {
        InterfaceOptionsBuilder {
            options: Self::default(),
        }
    }

    /// Relative distance (fraction of the length of the edge a projected point falls on) under
    /// which the point is the existing node; in (0, 0.5).
    pub fn snap_tolerance(&self) -> f64 {
        self.snap_tolerance
    }

    /// Smallest piece, as a fraction of the edge being cut, that an insertion may leave (a
    /// projected point closer than this to a node snaps to that node); in [0, 0.5).
    pub fn min_edge_fraction(&self) -> f64 {
        self.min_edge_fraction
    }

    /// Projections farther than this (distance along the normal) do not count: only parts
    /// closer than this face each other. `None`: any distance.
    pub fn max_distance(&self) -> Option<f64> {
        self.max_distance
    }

    /// True when a snapped pair of existing nodes is made to coincide (see the module
    /// documentation, "Snapping"): the node of one side moves onto the other side's
    /// projection where its chain is straight. `false` keeps both nodes where they are (the
    /// tangential misfit of the snapping stays).
    pub fn align_snapped_nodes(&self) -> bool {
        self.align_snapped_nodes
    }

    /// The fraction of an edge within which a projected point snaps to the edge's end node.
    pub(crate) fn snap_fraction(&self) -> f64 {
        self.snap_tolerance.max(self.min_edge_fraction)
    }

    /// Checks every setting: `snap_tolerance` in (0, 0.5), `min_edge_fraction` in [0, 0.5),
    /// `max_distance` positive and finite when given.
    pub(crate) fn validate(&self) -> Result<(), MeshError> {
        let invalid = |setting, value, requirement| {
            Err(MeshError::InvalidOption {
                setting,
                value,
                requirement,
            })
        };
        if !(self.snap_tolerance > 0.0 && self.snap_tolerance < 0.5) {
            return invalid("snap_tolerance", self.snap_tolerance, "in (0, 0.5)");
        }
        if !(self.min_edge_fraction >= 0.0 && self.min_edge_fraction < 0.5) {
            return invalid("min_edge_fraction", self.min_edge_fraction, "in [0, 0.5)");
        }
        match self.max_distance {
            Some(d) if !(d > 0.0 && d.is_finite()) => {
                invalid("max_distance", d, "positive and finite (or not given)")
            }
            _ => Ok(()),
        }
    }
}

/// Builder of [`InterfaceOptions`]; values are checked by [`InterfaceOptionsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct InterfaceOptionsBuilder {
    options: InterfaceOptions,
}

impl InterfaceOptionsBuilder {
    /// See [`InterfaceOptions::snap_tolerance`].
    pub fn snap_tolerance(mut self, value: f64) -> Self {
        self.options.snap_tolerance = value;
        self
    }

    /// See [`InterfaceOptions::min_edge_fraction`].
    pub fn min_edge_fraction(mut self, value: f64) -> Self {
        self.options.min_edge_fraction = value;
        self
    }

    /// See [`InterfaceOptions::max_distance`].
    pub fn max_distance(mut self, value: f64) -> Self {
        self.options.max_distance = Some(value);
        self
    }

    /// See [`InterfaceOptions::align_snapped_nodes`].
    pub fn align_snapped_nodes(mut self, value: bool) -> Self {
        self.options.align_snapped_nodes = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`MeshError::InvalidOption`] naming the first invalid setting.
    pub fn build(self) -> Result<InterfaceOptions, MeshError> {
        self.options.validate()?;
        Ok(self.options)
    }
}

/// One node of a boundary part ordered as a chain (see [`boundary_chain`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainNode {
    /// Vertex index in the mesh.
    pub vertex: usize,
    /// Its coordinates.
    pub point: Point,
    /// Outward unit nodal normal: the normalised mean of the outward unit normals of the one
    /// or two chain edges at the node.
    pub normal: Vector,
    /// Half the summed lengths of the one or two chain edges at the node.
    pub tributary_length: f64,
}

/// One node-to-node pair of an [`Interface`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfacePair {
    /// Vertex of the new mesh a.
    pub node_a: usize,
    /// Vertex of the new mesh b.
    pub node_b: usize,
    /// Coordinates of `node_a`.
    pub point_a: Point,
    /// Coordinates of `node_b`.
    pub point_b: Point,
    /// Outward unit normal of body a at `node_a` (nu_1; body b's is its negative).
    pub normal: Vector,
    /// Tributary length l_x of the node on side a (trapezoidal weight on the paired range).
    pub tributary_length: f64,
    /// Geometric initial gap `(point_b - point_a) . normal`; positive when open.
    pub initial_gap: f64,
}

/// Two meshes made node-to-node on their facing parts, and the pairing.
#[derive(Debug, Clone, PartialEq)]
pub struct Interface {
    /// Mesh a with the inserted vertices (old vertex indices unchanged, new ones appended).
    pub mesh_a: Mesh,
    /// Mesh b with the inserted vertices (old vertex indices unchanged, new ones appended).
    pub mesh_b: Mesh,
    /// Name of the interface part of mesh a.
    pub part_a: String,
    /// Name of the interface part of mesh b.
    pub part_b: String,
    /// The pairs, ordered along side a's chain.
    pub pairs: Vec<InterfacePair>,
    /// Number of vertices inserted into mesh a.
    pub inserted_a: usize,
    /// Number of vertices inserted into mesh b.
    pub inserted_b: usize,
}

/// Orders the edges of boundary part `part` of `mesh` into a chain, in the direction of the
/// body's counter-clockwise boundary, and returns its nodes with nodal normals and tributary
/// lengths.
///
/// Errors: [`MeshError::UnknownPart`] (listing the parts that exist), or
/// [`MeshError::Interface`] (with `part_a` = `part_b` = `part`) when the part is empty, branches,
/// is a closed loop, is made of several disjoint pieces, or folds back on itself.
///
/// ```
/// use vem_mesh::generators::{structured_quads, Rectangle};
/// use vem_mesh::interface::boundary_chain;
/// let mesh = structured_quads(&Rectangle::unit_square(), 4, 1)?;
/// let top = boundary_chain(&mesh, "top")?;
/// // The top runs from right to left (counter-clockwise), normals point up.
/// assert_eq!(top.first().unwrap().point.x, 1.0);
/// assert!(top.iter().all(|node| node.normal.y == 1.0));
/// assert_eq!(top[0].tributary_length, 0.125);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn boundary_chain(mesh: &Mesh, part: &str) -> Result<Vec<ChainNode>, MeshError> {
    let fail = |reason: String| MeshError::Interface {
        part_a: part.to_string(),
        part_b: part.to_string(),
        reason,
    };
    Ok(Chain::new(mesh, part, &fail)?.nodes)
}

/// A boundary part as a chain: node k and node k + 1 are joined by mesh edge `edges[k]`,
/// traversed in the direction of the edge's polygon (`Edge::vertices` order).
struct Chain {
    nodes: Vec<ChainNode>,
    edges: Vec<usize>,
}

impl Chain {
    fn new(mesh: &Mesh, part: &str, fail: &dyn Fn(String) -> MeshError) -> Result<Self, MeshError> {
        let part_edges = &mesh.part(part)?.edges;
        if part_edges.is_empty() {
            return Err(fail(format!("part '{part}' has no edges")));
        }
        let mut seen: HashSet<usize> = HashSet::with_capacity(part_edges.len());
        let mut outgoing: HashMap<usize, usize> = HashMap::with_capacity(part_edges.len());
        let mut incoming: HashSet<usize> = HashSet::with_capacity(part_edges.len());
        for &e in part_edges {
            let [a, b] = mesh.edge(e).vertices;
            if !seen.insert(e) {
                return Err(fail(format!("part '{part}' lists edge ({a}, {b}) twice")));
            }
            let branch = if outgoing.insert(a, e).is_some() {
                Some(a)
            } else if !incoming.insert(b) {
                Some(b)
            } else {
                None
            };
            if let Some(v) = branch {
                return Err(fail(format!(
                    "part '{part}' branches at vertex {v}: it is not a single chain"
                )));
            }
        }
        let mut starts: Vec<usize> = outgoing
            .keys()
            .copied()
            .filter(|v| !incoming.contains(v))
            .collect();
        starts.sort_unstable();
        let start = match starts.as_slice() {
            [] => {
                return Err(fail(format!(
                    "part '{part}' is a closed loop; an interface part must be an open chain"
                )))
            }
            [start] => *start,
            _ => {
                return Err(fail(format!(
                "part '{part}' is made of {} disjoint pieces (starting at vertices {starts:?}); \
                     it must be one open chain",
                starts.len()
            )))
            }
        };
        let mut vertices = vec![start];
        let mut edges = Vec::with_capacity(part_edges.len());
        let mut v = start;
        while let Some(&e) = outgoing.get(&v) {
            edges.push(e);
            v = mesh.edge(e).vertices[1];
            vertices.push(v);
        }
        if edges.len() != part_edges.len() {
            return Err(fail(format!(
                "part '{part}' is made of several disjoint pieces: the chain from vertex {start} \
                 has {} of its {} edges, the others form a closed loop",
                edges.len(),
                part_edges.len()
            )));
        }
        let points: Vec<Point> = vertices.iter().map(|&v| mesh.vertex(v)).collect();
        let edge_normals: Vec<Vector> = points
            .windows(2)
            .map(|w| geometry::outward_normal(w[0], w[1]))
            .collect();
        let tributary = tributary_lengths(&points);
        let mut nodes = Vec::with_capacity(vertices.len());
        for (k, &vertex) in vertices.iter().enumerate() {
            let before = k.checked_sub(1).map(|j| edge_normals[j]);
            let after = edge_normals.get(k).copied();
            let sum = before.unwrap_or_else(Vector::zeros) + after.unwrap_or_else(Vector::zeros);
            let norm = sum.norm();
            if norm < 1e-8 {
                return Err(fail(format!(
                    "part '{part}' folds back on itself at vertex {vertex}"
                )));
            }
            nodes.push(ChainNode {
                vertex,
                point: points[k],
                normal: sum / norm,
                tributary_length: tributary[k],
            });
        }
        Ok(Chain { nodes, edges })
    }

    fn n_edges(&self) -> usize {
        self.edges.len()
    }

    fn point(&self, k: usize) -> Point {
        self.nodes[k].point
    }

    /// Parameter window of edge k: a little more than [0, 1] at interior vertices, and up to
    /// `free_end` beyond the chain's two free ends.
    fn window(&self, k: usize, free_end: f64) -> (f64, f64) {
        let lo = if k == 0 { -free_end } else { -VERTEX_CROSSING };
        let hi = if k + 1 == self.n_edges() {
            1.0 + free_end
        } else {
            1.0 + VERTEX_CROSSING
        };
        (lo, hi)
    }
}

/// Trapezoidal weights of a polyline: half the lengths of the one or two segments at each point.
fn tributary_lengths(points: &[Point]) -> Vec<f64> {
    let mut weights = vec![0.0; points.len()];
    for k in 1..points.len() {
        let half = 0.5 * (points[k] - points[k - 1]).norm();
        weights[k - 1] += half;
        weights[k] += half;
    }
    weights
}

fn cross(a: Vector, b: Vector) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Where a projection lands on a chain: edge `edge` at parameter `s` in [0, 1], at signed
/// distance `distance` along the projection direction.
#[derive(Debug, Clone, Copy)]
struct Hit {
    edge: usize,
    s: f64,
    distance: f64,
}

/// Why projections were rejected, to explain a failure.
#[derive(Debug, Default)]
struct Rejections {
    back_facing: usize,
    nearest_too_far: Option<f64>,
}

impl Rejections {
    /// Keeps `hit` if it faces and is close enough, and if it is nearer than `best`.
    fn consider(
        &mut self,
        best: &mut Option<Hit>,
        hit: Hit,
        facing: bool,
        max_distance: Option<f64>,
    ) {
        if !facing {
            self.back_facing += 1;
            return;
        }
        if let Some(limit) = max_distance {
            if hit.distance.abs() > limit {
                let d = hit.distance.abs();
                self.nearest_too_far = Some(self.nearest_too_far.map_or(d, |n: f64| n.min(d)));
                return;
            }
        }
        if best.is_none_or(|b| hit.distance.abs() < b.distance.abs()) {
            *best = Some(hit);
        }
    }
}

/// Casts the line `origin + t dir` (t of either sign, `dir` a unit vector) against `target`
/// and returns the nearest crossing of an edge whose outward normal opposes `dir`.
fn ray_cast(
    origin: Point,
    dir: Vector,
    target: &Chain,
    free_end: f64,
    max_distance: Option<f64>,
    rejections: &mut Rejections,
) -> Option<Hit> {
    let mut best = None;
    for k in 0..target.n_edges() {
        let (p, q) = (target.point(k), target.point(k + 1));
        let d = q - p;
        let det = cross(dir, d);
        if det.abs() <= 1e-12 * d.norm() {
            continue; // parallel: no single crossing
        }
        // origin + t dir = p + s d
        let w = p - origin;
        let s = -cross(dir, w) / det;
        let (lo, hi) = target.window(k, free_end);
        if !(lo..=hi).contains(&s) {
            continue;
        }
        let hit = Hit {
            edge: k,
            s: s.clamp(0.0, 1.0),
            distance: cross(w, d) / det,
        };
        let facing = dir.dot(&geometry::outward_normal(p, q)) < 0.0;
        rejections.consider(&mut best, hit, facing, max_distance);
    }
    best
}

/// Projects `x` onto `target` along its normal field interpolated linearly between nodal
/// normals: finds s with x - (p + s d) parallel to n(s) = (1 - s) n_p + s n_q. Only points
/// where n(s) opposes `facing` (the projected node's own normal) count.
fn normal_field_projection(
    x: Point,
    facing: Vector,
    target: &Chain,
    free_end: f64,
    max_distance: Option<f64>,
    rejections: &mut Rejections,
) -> Option<Hit> {
    let mut best = None;
    for k in 0..target.n_edges() {
        let (p, q) = (target.point(k), target.point(k + 1));
        let (n_p, n_q) = (target.nodes[k].normal, target.nodes[k + 1].normal);
        let (d, dn, w) = (q - p, n_q - n_p, x - p);
        // cross(w - s d, n_p + s dn) = c + b s + a s^2 = 0
        let a = -cross(d, dn);
        let b = cross(w, dn) - cross(d, n_p);
        let c = cross(w, n_p);
        let mut roots = [f64::NAN; 2];
        if a.abs() <= 1e-12 * b.abs() {
            roots[0] = -c / b;
        } else {
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                continue;
            }
            let r = -0.5 * (b + b.signum() * disc.sqrt());
            roots = [r / a, c / r];
        }
        let (lo, hi) = target.window(k, free_end);
        for s in roots {
            if !(lo..=hi).contains(&s) {
                continue; // also rejects NaN
            }
            let s = s.clamp(0.0, 1.0);
            let normal = n_p + dn * s;
            let norm = normal.norm();
            if norm < 1e-8 {
                continue;
            }
            let hit = Hit {
                edge: k,
                s,
                distance: (x - (p + d * s)).dot(&normal) / norm,
            };
            rejections.consider(&mut best, hit, normal.dot(&facing) < 0.0, max_distance);
        }
    }
    best
}

/// A position on a chain: an existing node, or a point to insert on an edge.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Place {
    Node(usize),
    OnEdge { edge: usize, s: f64 },
}

impl Place {
    /// The node at `hit`, when within `snap` (fraction of the edge) of one; else a new point.
    fn snapped(hit: Hit, snap: f64) -> Self {
        if hit.s < snap {
            Place::Node(hit.edge)
        } else if hit.s > 1.0 - snap {
            Place::Node(hit.edge + 1)
        } else {
            Place::OnEdge {
                edge: hit.edge,
                s: hit.s,
            }
        }
    }

    /// Chain parameter: node k is at k, a point on edge k at k + s.
    fn xi(self) -> f64 {
        match self {
            Place::Node(k) => k as f64,
            Place::OnEdge { edge, s } => edge as f64 + s,
        }
    }

    fn node(self) -> Option<usize> {
        match self {
            Place::Node(k) => Some(k),
            Place::OnEdge { .. } => None,
        }
    }

    fn point(self, chain: &Chain) -> Point {
        match self {
            Place::Node(k) => chain.point(k),
            Place::OnEdge { edge, s } => {
                chain.point(edge) + (chain.point(edge + 1) - chain.point(edge)) * s
            }
        }
    }
}

/// A future interface pair: where it lies on chain a and on chain b.
#[derive(Debug, Clone, Copy)]
struct Station {
    a: Place,
    b: Place,
}

/// Makes the boundary parts `part_a` of `mesh_a` and `part_b` of `mesh_b` node-to-node and
/// returns the new meshes with the node pairing (see the [module documentation](crate::interface) for the
/// conventions, the projections and the snapping rule).
///
/// Each part must be one open chain. The boundary edge (u, v) of polygon P that receives points
/// m_1, ..., m_k becomes (u, m_1), ..., (m_k, v): only P's vertex loop changes, and every
/// boundary part containing the edge gets the pieces instead.
///
/// Errors ([`MeshError::Interface`] unless noted): an unknown part
/// ([`MeshError::UnknownPart`], naming the parts that exist); invalid options; a part that is
/// not one open chain; parts that do not face each other (no projection hits, the normals point
/// the same way, or all hits are farther than `max_distance`); a node inside the overlap whose
/// projection misses; a pairing that is not monotone along the chains or would leave a sliver
/// edge between two inserted points (the meshes' sizes differ by more than 1/`min_edge_fraction`
/// there, or the parts curve too much for their distance).
pub fn insert_interface_nodes(
    mesh_a: &Mesh,
    part_a: &str,
    mesh_b: &Mesh,
    part_b: &str,
    options: &InterfaceOptions,
) -> Result<Interface, MeshError> {
    let fail = |reason: String| MeshError::Interface {
        part_a: part_a.to_string(),
        part_b: part_b.to_string(),
        reason,
    };
    options.validate()?;
    let chain_a = Chain::new(mesh_a, part_a, &fail)?;
    let chain_b = Chain::new(mesh_b, part_b, &fail)?;
    let snap = options.snap_fraction();
    let mut rejections = Rejections::default();

    // Nodes of a along their normals onto b; nodes of b along a's normal field onto a.
    let hits_a: Vec<Option<Hit>> = chain_a
        .nodes
        .iter()
        .map(|node| {
            ray_cast(
                node.point,
                node.normal,
                &chain_b,
                snap,
                options.max_distance,
                &mut rejections,
            )
        })
        .collect();
    let hits_b: Vec<Option<Hit>> = chain_b
        .nodes
        .iter()
        .map(|node| {
            normal_field_projection(
                node.point,
                node.normal,
                &chain_a,
                snap,
                options.max_distance,
                &mut rejections,
            )
        })
        .collect();
    if hits_a.iter().chain(&hits_b).all(Option::is_none) {
        let mut reason = String::from(
            "the parts do not face each other: no node of either projects onto the other",
        );
        if let Some(d) = rejections.nearest_too_far {
            reason += &format!(" within max_distance (nearest: {d:e})");
        }
        if rejections.back_facing > 0 {
            reason += " (their outward normals do not oppose each other)";
        }
        return Err(fail(reason));
    }
    check_contiguous(&hits_a, &chain_a, part_a, part_b, &fail)?;
    check_contiguous(&hits_b, &chain_b, part_b, part_a, &fail)?;

    let mut stations: Vec<Station> = Vec::with_capacity(hits_a.len() + hits_b.len());
    for (i, hit) in hits_a.iter().enumerate() {
        if let Some(hit) = hit {
            stations.push(Station {
                a: Place::Node(i),
                b: Place::snapped(*hit, snap),
            });
        }
    }
    for (j, hit) in hits_b.iter().enumerate() {
        if let Some(hit) = hit {
            stations.push(Station {
                a: Place::snapped(*hit, snap),
                b: Place::Node(j),
            });
        }
    }
    let stations = merge_stations(stations, &chain_a, &chain_b, snap, &fail)?;
    let (moves_a, moves_b) = if options.align_snapped_nodes {
        aligning_moves(&stations, &chain_a, &chain_b, &hits_a, &hits_b, snap)
    } else {
        (Vec::new(), Vec::new())
    };

    // The two meshes are independent: b on a thread of its own.
    let (a, b) = std::thread::scope(|scope| {
        let b = scope
            .spawn(|| insert_points(mesh_b, &chain_b, stations.iter().map(|st| st.b), &moves_b));
        let a = insert_points(mesh_a, &chain_a, stations.iter().map(|st| st.a), &moves_a);
        (
            a,
            b.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
        )
    });
    let (new_a, vertices_a, inserted_a) = a?;
    let (new_b, vertices_b, inserted_b) = b?;

    // Normals from the new chain of a (spec: nu_1 at the node); lengths on the paired range.
    let new_chain_a = Chain::new(&new_a, part_a, &fail)?;
    let normal_of: HashMap<usize, Vector> = new_chain_a
        .nodes
        .iter()
        .map(|node| (node.vertex, node.normal))
        .collect();
    let points_a: Vec<Point> = vertices_a.iter().map(|&v| new_a.vertex(v)).collect();
    let tributary = tributary_lengths(&points_a);
    let mut pairs = Vec::with_capacity(stations.len());
    for (k, (&node_a, &node_b)) in vertices_a.iter().zip(&vertices_b).enumerate() {
        let normal = *normal_of.get(&node_a).ok_or_else(|| {
            fail(format!(
                "inserted vertex {node_a} is not on the new chain of '{part_a}'"
            ))
        })?;
        let (point_a, point_b) = (new_a.vertex(node_a), new_b.vertex(node_b));
        pairs.push(InterfacePair {
            node_a,
            node_b,
            point_a,
            point_b,
            normal,
            tributary_length: tributary[k],
            initial_gap: (point_b - point_a).dot(&normal),
        });
    }
    Ok(Interface {
        mesh_a: new_a,
        mesh_b: new_b,
        part_a: part_a.to_string(),
        part_b: part_b.to_string(),
        pairs,
        inserted_a,
        inserted_b,
    })
}

/// The nodes of `chain` (part `part`) that project onto part `other` must be consecutive:
/// a miss between two hits is a node inside the overlap without a partner.
fn check_contiguous(
    hits: &[Option<Hit>],
    chain: &Chain,
    part: &str,
    other: &str,
    fail: &dyn Fn(String) -> MeshError,
) -> Result<(), MeshError> {
    let first = hits.iter().position(Option::is_some);
    let last = hits.iter().rposition(Option::is_some);
    if let (Some(first), Some(last)) = (first, last) {
        if let Some(k) = (first..=last).find(|&k| hits[k].is_none()) {
            let node = chain.nodes[k];
            return Err(fail(format!(
                "vertex {} of '{part}' at ({}, {}) does not project onto '{other}' (a miss, \
                 back-facing, or beyond max_distance) although vertices {} and {} on either \
                 side of it do",
                node.vertex,
                node.point.x,
                node.point.y,
                chain.nodes[first].vertex,
                chain.nodes[last].vertex
            )));
        }
    }
    Ok(())
}

/// Sorts the stations along chain a, merges those that share a node (snapped coincidences),
/// and checks that the result is strictly monotone along both chains (a forwards, b
/// backwards) and leaves no sliver between two inserted points.
fn merge_stations(
    mut stations: Vec<Station>,
    chain_a: &Chain,
    chain_b: &Chain,
    snap: f64,
    fail: &dyn Fn(String) -> MeshError,
) -> Result<Vec<Station>, MeshError> {
    stations.sort_by(|x, y| {
        x.a.xi()
            .total_cmp(&y.a.xi())
            .then(y.b.xi().total_cmp(&x.b.xi()))
    });
    let describe = |st: &Station| {
        let (pa, pb) = (st.a.point(chain_a), st.b.point(chain_b));
        format!("({}, {}) on a and ({}, {}) on b", pa.x, pa.y, pb.x, pb.y)
    };
    let conflict = |first: &Station, second: &Station| {
        fail(format!(
            "two different nodes would pair with one node: {} versus {}; the meshes' sizes \
             differ by more than 1/min_edge_fraction here, or the parts curve too much for \
             their distance",
            describe(first),
            describe(second)
        ))
    };
    let mut merged: Vec<Station> = Vec::with_capacity(stations.len());
    for st in stations {
        if let Some(last) = merged.last_mut() {
            let shares_a = last.a.node().is_some() && last.a.node() == st.a.node();
            let shares_b = last.b.node().is_some() && last.b.node() == st.b.node();
            if shares_a || shares_b {
                let pick = |x: Place, y: Place| match (x, y) {
                    (Place::Node(i), Place::Node(j)) if i != j => None,
                    (Place::OnEdge { .. }, node @ Place::Node(_)) => Some(node),
                    (x, _) => Some(x),
                };
                match (pick(last.a, st.a), pick(last.b, st.b)) {
                    (Some(a), Some(b)) => *last = Station { a, b },
                    _ => return Err(conflict(last, &st)),
                }
                continue;
            }
        }
        merged.push(st);
    }
    if merged.len() < 2 {
        return Err(fail(format!(
            "the parts overlap in a single point ({}), not along a curve",
            merged.first().map_or_else(String::new, describe)
        )));
    }
    for w in merged.windows(2) {
        let (x, y) = (&w[0], &w[1]);
        if !(y.a.xi() > x.a.xi() && y.b.xi() < x.b.xi()) {
            return Err(fail(format!(
                "the pairing is not monotone along the parts between {} and {}: the parts \
                 curve too much for their distance, or do not face each other there",
                describe(x),
                describe(y)
            )));
        }
        for (p, q) in [(x.a, y.a), (x.b, y.b)] {
            if let (Place::OnEdge { edge: e, s }, Place::OnEdge { edge: f, s: t }) = (p, q) {
                if e == f && (t - s).abs() < snap {
                    return Err(fail(format!(
                        "two inserted points would be closer than {snap} of their edge: {} \
                         and {}; the meshes' sizes differ by more than 1/min_edge_fraction here",
                        describe(x),
                        describe(y)
                    )));
                }
            }
        }
    }
    Ok(merged)
}

/// True when node `k` of `chain` is interior and its two chain edges are collinear (to
/// rounding) and run the same way: moving it along the chain keeps the body's shape.
fn straight_at(chain: &Chain, k: usize) -> bool {
    if k == 0 || k + 1 >= chain.nodes.len() {
        return false;
    }
    let before = chain.point(k) - chain.point(k - 1);
    let after = chain.point(k + 1) - chain.point(k);
    let scale = before.norm() * after.norm();
    scale > 0.0 && cross(before, after).abs() <= 1e-12 * scale && before.dot(&after) > 0.0
}

/// The point of `chain` at `hit`, when `hit` lies on an edge next to node `k` within `snap`
/// of that edge's length from the node; `None` otherwise.
fn landing_next_to(chain: &Chain, hit: Option<Hit>, k: usize, snap: f64) -> Option<Point> {
    let hit = hit?;
    let near = (hit.edge == k && hit.s <= snap) || (hit.edge + 1 == k && hit.s >= 1.0 - snap);
    near.then(|| {
        let (p, q) = (chain.point(hit.edge), chain.point(hit.edge + 1));
        p + (q - p) * hit.s
    })
}

/// A vertex and its new position.
type VertexMove = (usize, Point);

/// The vertex moves that make every snapped pair of existing nodes coincide (see the module
/// documentation, "Snapping"): (vertex, new position) for mesh a and for mesh b.
fn aligning_moves(
    stations: &[Station],
    chain_a: &Chain,
    chain_b: &Chain,
    hits_a: &[Option<Hit>],
    hits_b: &[Option<Hit>],
    snap: f64,
) -> (Vec<VertexMove>, Vec<VertexMove>) {
    let (mut moves_a, mut moves_b) = (Vec::new(), Vec::new());
    for st in stations {
        let (Place::Node(i), Place::Node(j)) = (st.a, st.b) else {
            continue;
        };
        if chain_a.point(i) == chain_b.point(j) {
            continue;
        }
        if straight_at(chain_b, j) {
            if let Some(target) = landing_next_to(chain_b, hits_a[i], j, snap) {
                moves_b.push((chain_b.nodes[j].vertex, target));
                continue;
            }
        }
        if straight_at(chain_a, i) {
            if let Some(target) = landing_next_to(chain_a, hits_b[j], i, snap) {
                moves_a.push((chain_a.nodes[i].vertex, target));
            }
        }
    }
    (moves_a, moves_b)
}

/// Moves the vertices `moves` (aligned snapped nodes), inserts the `OnEdge` places into `mesh`
/// (new vertices appended, in order of appearance) and returns the new mesh, the vertex of
/// every place, and the number of inserted vertices.
fn insert_points(
    mesh: &Mesh,
    chain: &Chain,
    places: impl Iterator<Item = Place>,
    moves: &[VertexMove],
) -> Result<(Mesh, Vec<usize>, usize), MeshError> {
    let places: Vec<Place> = places.collect();
    let on_edges = places
        .iter()
        .filter(|p| matches!(p, Place::OnEdge { .. }))
        .count();
    let mut vertices = Vec::with_capacity(mesh.n_vertices() + on_edges);
    vertices.extend_from_slice(mesh.vertices());
    for &(v, point) in moves {
        vertices[v] = point;
    }
    // Directed edge (as its polygon traverses it) -> inserted vertices with their parameter.
    let mut on_edge: HashMap<(usize, usize), Vec<(f64, usize)>> = HashMap::new();
    let mut place_vertices = Vec::new();
    for place in places {
        let vertex = match place {
            Place::Node(k) => chain.nodes[k].vertex,
            Place::OnEdge { edge, s } => {
                vertices.push(place.point(chain));
                let [u, v] = mesh.edge(chain.edges[edge]).vertices;
                on_edge
                    .entry((u, v))
                    .or_default()
                    .push((s, vertices.len() - 1));
                vertices.len() - 1
            }
        };
        place_vertices.push(vertex);
    }
    let inserted = vertices.len() - mesh.n_vertices();
    if inserted == 0 && moves.is_empty() {
        return Ok((mesh.clone(), place_vertices, 0));
    }
    let pieces: HashMap<(usize, usize), Vec<usize>> = on_edge
        .into_iter()
        .map(|(key, mut list)| {
            list.sort_by(|x, y| x.0.total_cmp(&y.0));
            (key, list.into_iter().map(|(_, v)| v).collect())
        })
        .collect();
    let mut offsets = Vec::with_capacity(mesh.n_polygons() + 1);
    offsets.push(0);
    let mut indices = Vec::with_capacity(mesh.polygon_vertex_indices().len() + inserted);
    // The vertices an edge with inserted points starts from: the map is asked about their
    // edges only (a few hundred of the mesh's sides).
    let mut starts_pieces = vec![false; mesh.n_vertices()];
    for &(u, _) in pieces.keys() {
        starts_pieces[u] = true;
    }
    for polygon in mesh.polygons() {
        for (k, &u) in polygon.iter().enumerate() {
            indices.push(u);
            if starts_pieces[u] {
                let v = polygon[(k + 1) % polygon.len()];
                if let Some(list) = pieces.get(&(u, v)) {
                    indices.extend_from_slice(list);
                }
            }
        }
        offsets.push(indices.len());
    }
    let parts: Vec<PartSpec> = mesh
        .part_specs()
        .into_iter()
        .map(|spec| {
            let mut edges = Vec::with_capacity(spec.edges.len());
            for [u, v] in spec.edges {
                let (list, forward) = match (pieces.get(&(u, v)), pieces.get(&(v, u))) {
                    (Some(list), _) => (list, true),
                    (None, Some(list)) => (list, false),
                    (None, None) => {
                        edges.push([u, v]);
                        continue;
                    }
                };
                let mut run = vec![u];
                if forward {
                    run.extend(list.iter().copied());
                } else {
                    run.extend(list.iter().rev().copied());
                }
                run.push(v);
                edges.extend(run.windows(2).map(|w| [w[0], w[1]]));
            }
            PartSpec::new(spec.name, edges)
        })
        .collect();
    // Only the polygons at the moved and inserted vertices changed: they are validated, not
    // the whole mesh again.
    let changed: Vec<usize> = moves
        .iter()
        .map(|&(v, _)| v)
        .chain(mesh.n_vertices()..mesh.n_vertices() + inserted)
        .collect();
    let new_mesh = Mesh::from_compact_changed(vertices, offsets, indices, parts, &changed)?;
    Ok((new_mesh, place_vertices, inserted))
}
