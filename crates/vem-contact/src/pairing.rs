//! The geometry of a contact pair: interface node insertion between two bodies, or the nodes
//! of a body's contact part facing an obstacle. The only place of the contact layer where the
//! dimension changes the code: in 2D the parts are chains of edges
//! ([`vem_mesh::interface`]); in 3D they are surfaces of faces ([`crate::surface`]), and a pair
//! of two bodies is made node-to-node by the surface overlay
//! ([`vem_mesh::polyhedral::overlay::insert_surface_overlay`]).

use std::any::Any;
use std::collections::HashMap;
use std::sync::Arc;

use vem_elastic::ElasticBody;
use vem_mesh::interface::{boundary_chain, insert_interface_nodes, ChainNode};
use vem_mesh::{BodyMesh, Mesh, PointD, PolyhedralMesh, VectorD};

use crate::problem::{ContactPair, Counterpart};
use vem_mesh::polyhedral::overlay::{boundary_surface, insert_surface_overlay, SurfaceInterface};

use crate::surface::open_rim;
use crate::warning::ZoneLimit;
use crate::{ContactError, ContactNode, Location};

/// What the geometry of one pair gives: its nodes (ordered along body A's part in 2D), the
/// vertices inserted, the ends of the modelled interface that may cut a contact zone short,
/// and whether the nodes form a chain (2D) along which the consistent traction is projected,
/// or in 3D the faces (loops of the pair's node indices) of the surface on which it is.
pub(crate) struct PairGeometry<const D: usize> {
    pub(crate) nodes: Vec<ContactNode<D>>,
    pub(crate) inserted: usize,
    pub(crate) zone_ends: Vec<ZoneEnd>,
    pub(crate) chain: bool,
    pub(crate) surface: Option<Vec<Vec<usize>>>,
}

/// An end of a pair's modelled interface that is not a geometric end of the contact: the
/// nodes beyond were left unpaired by the pairing limit, or a contact part ends there while
/// its body's boundary goes on (no convex corner). A contact zone that reaches it may be
/// clipped.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ZoneEnd {
    /// The pair's node at the end.
    pub(crate) node: usize,
    /// What lies beyond.
    pub(crate) limit: ZoneLimit,
    /// The body whose part ends there (body A at the pairing limit).
    pub(crate) body: usize,
    /// That part.
    pub(crate) part: String,
}

/// A contact part that ends where its body's boundary turns away by at least this angle (a
/// convex corner: 45 degrees) ends where the contact must end; a part that ends where the
/// boundary goes on straighter could be cut short by its own end.
const CORNER_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// The angle by which the boundary of `mesh` turns at the first (`at_start`) or last node of
/// `chain` (a part, ordered along the counter-clockwise boundary), from the direction in which
/// it arrives to that in which it leaves: positive for a left turn (a convex corner, the
/// boundary beyond faces away from the part's outside), negative at a concave corner. `None`
/// when the part has fewer than two nodes or no other boundary edge meets that node.
fn boundary_turn(mesh: &Mesh, chain: &[ChainNode], at_start: bool) -> Option<f64> {
    let n = chain.len();
    if n < 2 {
        return None;
    }
    let (v, inner) = if at_start {
        (chain[0].vertex, chain[1].vertex)
    } else {
        (chain[n - 1].vertex, chain[n - 2].vertex)
    };
    let other = mesh
        .boundary_edges()
        .map(|e| mesh.edge(e).vertices)
        .find(|&[a, b]| {
            if at_start {
                b == v && a != inner
            } else {
                a == v && b != inner
            }
        })?;
    let p = |k: usize| mesh.vertex(k);
    let (arriving, leaving) = if at_start {
        (p(v) - p(other[0]), p(inner) - p(v))
    } else {
        (p(v) - p(inner), p(other[1]) - p(v))
    };
    Some(arriving.perp(&leaving).atan2(arriving.dot(&leaving)))
}

/// Whether the part `chain` of `mesh` ends at a convex corner of its body at its first
/// (`at_start`) or last node: the contact cannot go on beyond it.
fn ends_at_corner(mesh: &Mesh, chain: &[ChainNode], at_start: bool) -> bool {
    boundary_turn(mesh, chain, at_start).is_some_and(|turn| turn >= CORNER_TURN)
}

/// `value` as a `U` when `T` and `U` are the same type (the same dimension).
fn same<T: 'static, U: 'static>(value: T) -> Option<U> {
    let boxed: Box<dyn Any> = Box::new(value);
    boxed.downcast::<U>().ok().map(|b| *b)
}

fn point<const D: usize>(coords: &[f64]) -> PointD<D> {
    PointD::<D>::from_slice(coords)
}

fn vector<const D: usize>(coords: &[f64]) -> VectorD<D> {
    VectorD::<D>::from_column_slice(coords)
}

/// The planar mesh of a body in `D = 2`.
fn planar<const D: usize>(body: &ElasticBody<D>) -> Option<&Mesh> {
    body.body_mesh().as_planar()
}

/// The geometry of pair `index` of `bodies`; a pair of two bodies replaces both bodies by
/// themselves on their meshes enlarged by the insertion.
pub(crate) fn pair_geometry<const D: usize>(
    bodies: &mut [ElasticBody<D>],
    pair: &ContactPair<D>,
    index: usize,
) -> Result<PairGeometry<D>, ContactError> {
    let n_bodies = bodies.len();
    let check = |b: usize| {
        if b < n_bodies {
            Ok(())
        } else {
            Err(ContactError::InvalidSetting {
                reason: format!(
                    "contact pair {index} names body {b}, but the problem has {n_bodies} bodies"
                ),
            })
        }
    };
    let a = pair.body();
    check(a)?;
    let part = pair.part();
    let mut geometry = match pair.counterpart() {
        Counterpart::Body {
            body: b,
            part: other_part,
        } => {
            check(*b)?;
            if *b == a {
                return Err(ContactError::InvalidSetting {
                    reason: format!(
                        "contact pair {index}: body '{}' against itself is not supported",
                        bodies[a].name()
                    ),
                });
            }
            two_bodies(bodies, pair, index, a, *b, other_part)?
        }
        Counterpart::Obstacle(obstacle) => {
            obstacle.validate()?;
            obstacle_nodes(&bodies[a], a, part, index, &**obstacle)?
        }
    };
    if let Some(imposed) = pair.imposed_gap() {
        for node in &mut geometry.nodes {
            let h0: f64 = imposed(node.position);
            if !h0.is_finite() {
                return Err(ContactError::InvalidSetting {
                    reason: format!(
                        "imposed gap {h0} at {} is not finite",
                        Location::of(&node.position)
                    ),
                });
            }
            node.initial_gap += h0;
        }
    }
    Ok(geometry)
}

fn two_bodies<const D: usize>(
    bodies: &mut [ElasticBody<D>],
    pair: &ContactPair<D>,
    index: usize,
    a: usize,
    b: usize,
    other_part: &str,
) -> Result<PairGeometry<D>, ContactError> {
    let part = pair.part();
    if let (Some(mesh_a), Some(mesh_b)) = (
        bodies[a].body_mesh().as_polyhedral(),
        bodies[b].body_mesh().as_polyhedral(),
    ) {
        let (name_a, name_b) = (bodies[a].name(), bodies[b].name());
        let interface =
            insert_surface_overlay(mesh_a, part, mesh_b, other_part, pair.interface_options())
                .map_err(|source| ContactError::Mesh {
                    context: format!(
                        "contact pair {index}: surface overlay of '{part}' of body '{name_a}' \
                         and '{other_part}' of body '{name_b}'"
                    ),
                    source,
                })?;
        return two_bodies_on_surface(bodies, pair, index, a, b, interface);
    }
    let (Some(mesh_a), Some(mesh_b)) = (planar(&bodies[a]), planar(&bodies[b])) else {
        return Err(ContactError::Unsupported {
            what: format!(
                "contact pair {index}: interface insertion between two bodies in {D}D is not \
                 available"
            ),
        });
    };
    let (name_a, name_b) = (bodies[a].name().to_string(), bodies[b].name().to_string());
    let interface =
        insert_interface_nodes(mesh_a, part, mesh_b, other_part, pair.interface_options())
            .map_err(|source| ContactError::Mesh {
                context: format!(
            "interface between '{part}' of body '{name_a}' and '{other_part}' of body '{name_b}'"
        ),
                source,
            })?;
    let inserted = interface.inserted_a + interface.inserted_b;
    // Body A's and body B's chains on the enlarged meshes: at each end of the paired range,
    // the part that ends there (if any) and whether its body ends there too.
    let chain = boundary_chain(&interface.mesh_a, part).map_err(|source| ContactError::Mesh {
        context: format!("contact part of body '{name_a}'"),
        source,
    })?;
    let chain_b =
        boundary_chain(&interface.mesh_b, other_part).map_err(|source| ContactError::Mesh {
            context: format!("contact part of body '{name_b}'"),
            source,
        })?;
    let end_of = |chain: &[ChainNode], vertex: usize| {
        if chain.first().is_some_and(|c| c.vertex == vertex) {
            Some(true)
        } else if chain.last().is_some_and(|c| c.vertex == vertex) {
            Some(false)
        } else {
            None
        }
    };
    let zone_end = |node: usize, p: &vem_mesh::interface::InterfacePair| {
        let end_a = end_of(&chain, p.node_a);
        let end_b = end_of(&chain_b, p.node_b);
        let corner_a = end_a.is_some_and(|s| ends_at_corner(&interface.mesh_a, &chain, s));
        let corner_b = end_b.is_some_and(|s| ends_at_corner(&interface.mesh_b, &chain_b, s));
        let (limit, body, part) = match (end_a, end_b) {
            // The body of a part that ends there ends too: the contact ends there.
            _ if corner_a || corner_b => return None,
            (Some(_), _) => (ZoneLimit::EndOfPart, a, part),
            (None, Some(_)) => (ZoneLimit::EndOfPart, b, other_part),
            // Both parts go on: the nodes beyond were left unpaired.
            (None, None) => (ZoneLimit::PairingLimit, a, part),
        };
        Some(ZoneEnd {
            node,
            limit,
            body,
            part: part.to_string(),
        })
    };
    let n = interface.pairs.len();
    let mut zone_ends = Vec::new();
    if let Some(first) = interface.pairs.first() {
        zone_ends.extend(zone_end(0, first));
    }
    if let (Some(last), true) = (interface.pairs.last(), n > 1) {
        zone_ends.extend(zone_end(n - 1, last));
    }
    // Body B's outward nodal normals on its enlarged chain, for the normal choice.
    let normal_b: HashMap<usize, vem_mesh::Vector> =
        chain_b.iter().map(|c| (c.vertex, c.normal)).collect();
    let choice = pair.normal();
    let nodes: Vec<ContactNode<D>> = interface
        .pairs
        .iter()
        .map(|p| {
            let n_b = normal_b.get(&p.node_b).copied().unwrap_or(-p.normal);
            let normal = choice.combine(p.normal, n_b);
            let gap = (p.point_b - p.point_a).dot(&normal);
            ContactNode {
                pair: index,
                body_a: a,
                vertex_a: p.node_a,
                body_b: Some(b),
                vertex_b: Some(p.node_b),
                position: point(p.point_a.coords.as_slice()),
                normal: vector(normal.as_slice()),
                tributary_measure: p.tributary_length,
                geometric_gap: gap,
                initial_gap: gap,
            }
        })
        .collect();
    let enlarged = |mesh: Mesh| {
        same::<Arc<dyn BodyMesh<2>>, Arc<dyn BodyMesh<D>>>(Arc::new(mesh))
            .expect("a planar mesh is a body mesh of dimension 2")
    };
    bodies[a] = bodies[a].on_mesh(enlarged(interface.mesh_a))?;
    bodies[b] = bodies[b].on_mesh(enlarged(interface.mesh_b))?;
    Ok(PairGeometry {
        nodes,
        inserted,
        zone_ends,
        chain: true,
        surface: None,
    })
}

/// The geometry of a pair of two bodies in space from their surface interface `interface`
/// (side a body `a`'s part, side b body `b`'s): the node pairs, the normal of the side the pair
/// chooses, the ends of the modelled interface, the faces of side a's part on which the
/// consistent pressure is projected; the bodies are replaced by themselves on the enlarged
/// meshes when nodes were inserted.
fn two_bodies_on_surface<const D: usize>(
    bodies: &mut [ElasticBody<D>],
    pair: &ContactPair<D>,
    index: usize,
    a: usize,
    b: usize,
    interface: SurfaceInterface,
) -> Result<PairGeometry<D>, ContactError> {
    let (name_a, name_b) = (bodies[a].name().to_string(), bodies[b].name().to_string());
    let (part_a, part_b) = (interface.part_a.as_str(), interface.part_b.as_str());
    let mesh_error = |name: &str, part: &str| {
        let context = format!("contact part '{part}' of body '{name}'");
        move |source| ContactError::Mesh { context, source }
    };
    // Body B's outward nodal normals on its enlarged part, for the normal choice.
    let normal_b: HashMap<usize, vem_mesh::Vector3> = boundary_surface(&interface.mesh_b, part_b)
        .map_err(mesh_error(&name_b, part_b))?
        .into_iter()
        .map(|s| (s.vertex, s.normal))
        .collect();
    let rim_a = open_rim(&interface.mesh_a, part_a).map_err(mesh_error(&name_a, part_a))?;
    let rim_b = open_rim(&interface.mesh_b, part_b).map_err(mesh_error(&name_b, part_b))?;
    let on_rim_a = |v: usize| rim_a.binary_search(&v).is_ok();
    let on_rim_b = |v: usize| rim_b.binary_search(&v).is_ok();
    let choice = pair.normal();
    let mut zone_ends = Vec::new();
    let mut nodes: Vec<ContactNode<D>> = Vec::with_capacity(interface.pairs.len());
    for (k, p) in interface.pairs.iter().enumerate() {
        let n_b = normal_b.get(&p.node_b).copied().unwrap_or(-p.normal);
        let normal = choice.combine(p.normal, n_b);
        let gap = (p.point_b - p.point_a).dot(&normal);
        // A rim vertex of a part is an end of the modelled interface unless the body ends
        // there too (a convex corner: not on the open rim); a pair in the middle of both
        // parts is not an end.
        let (end_a, end_b) = (on_rim_a(p.node_a), on_rim_b(p.node_b));
        if end_a {
            zone_ends.push(ZoneEnd {
                node: k,
                limit: ZoneLimit::EndOfPart,
                body: a,
                part: part_a.to_string(),
            });
        } else if end_b {
            zone_ends.push(ZoneEnd {
                node: k,
                limit: ZoneLimit::EndOfPart,
                body: b,
                part: part_b.to_string(),
            });
        }
        nodes.push(ContactNode {
            pair: index,
            body_a: a,
            vertex_a: p.node_a,
            body_b: Some(b),
            vertex_b: Some(p.node_b),
            position: point(p.point_a.coords.as_slice()),
            normal: vector(normal.as_slice()),
            tributary_measure: p.tributary_area,
            geometric_gap: gap,
            initial_gap: gap,
        });
    }
    let index_of: HashMap<usize, usize> = interface
        .pairs
        .iter()
        .enumerate()
        .map(|(k, p)| (p.node_a, k))
        .collect();
    let surface =
        surface_faces(&interface.mesh_a, part_a, &index_of).map_err(mesh_error(&name_a, part_a))?;
    let inserted = interface.inserted_a + interface.inserted_b;
    if inserted > 0 {
        let enlarged = |mesh: PolyhedralMesh| {
            same::<Arc<dyn BodyMesh<3>>, Arc<dyn BodyMesh<D>>>(Arc::new(mesh))
                .expect("a polyhedral mesh is a body mesh of dimension 3")
        };
        bodies[a] = bodies[a].on_mesh(enlarged(interface.mesh_a))?;
        bodies[b] = bodies[b].on_mesh(enlarged(interface.mesh_b))?;
    }
    Ok(PairGeometry {
        nodes,
        inserted,
        zone_ends,
        chain: false,
        surface: Some(surface),
    })
}

/// The faces of `part` of `mesh` as loops of node indices (`index_of`: vertex to node), the
/// faces with a vertex that is not a node left out.
fn surface_faces(
    mesh: &PolyhedralMesh,
    part: &str,
    index_of: &HashMap<usize, usize>,
) -> Result<Vec<Vec<usize>>, vem_mesh::MeshError> {
    Ok(mesh
        .part_faces(part)?
        .iter()
        .filter_map(|&f| {
            mesh.face(f)
                .iter()
                .map(|v| index_of.get(v).copied())
                .collect::<Option<Vec<usize>>>()
        })
        .collect())
}

/// The nodes of `part` of `body` facing `obstacle`: in 2D along the part's chain (tributary
/// lengths of the trapezoidal rule), in 3D the part's vertices with the tributary areas of
/// their faces (each face's area shared equally by its vertices).
fn obstacle_nodes<const D: usize>(
    body: &ElasticBody<D>,
    body_index: usize,
    part: &str,
    index: usize,
    obstacle: &dyn crate::RigidObstacle<D>,
) -> Result<PairGeometry<D>, ContactError> {
    let mesh_error = |source| ContactError::Mesh {
        context: format!("contact part of body '{}'", body.name()),
        source,
    };
    let node = |vertex: usize, position: PointD<D>, measure: f64| {
        let contact = obstacle.gap_at(position);
        ContactNode {
            pair: index,
            body_a: body_index,
            vertex_a: vertex,
            body_b: None,
            vertex_b: None,
            position,
            normal: contact.normal,
            tributary_measure: measure,
            geometric_gap: contact.gap,
            initial_gap: contact.gap,
        }
    };
    if let Some(mesh) = planar(body) {
        let chain = boundary_chain(mesh, part).map_err(mesh_error)?;
        let nodes: Vec<ContactNode<D>> = chain
            .iter()
            .map(|c| {
                node(
                    c.vertex,
                    point(c.point.coords.as_slice()),
                    c.tributary_length,
                )
            })
            .collect();
        // An end of the part where the body's boundary goes on may cut the zone short.
        let n = nodes.len();
        let mut zone_ends = Vec::new();
        for (node, at_start) in [(0, true), (n.saturating_sub(1), false)] {
            if n > 0 && (at_start || n > 1) && !ends_at_corner(mesh, &chain, at_start) {
                zone_ends.push(ZoneEnd {
                    node,
                    limit: ZoneLimit::EndOfPart,
                    body: body_index,
                    part: part.to_string(),
                });
            }
        }
        return Ok(PairGeometry {
            nodes,
            inserted: 0,
            zone_ends,
            chain: true,
            surface: None,
        });
    }
    let Some(mesh) = body.body_mesh().as_polyhedral() else {
        return Err(ContactError::Unsupported {
            what: format!("contact pair {index}: contact parts in {D}D"),
        });
    };
    let vertices = boundary_surface(mesh, part).map_err(mesh_error)?;
    let nodes: Vec<ContactNode<D>> = vertices
        .iter()
        .map(|s| node(s.vertex, point(s.point.coords.as_slice()), s.tributary_area))
        .collect();
    // A rim vertex where the body's boundary goes on may cut the zone short.
    let rim = open_rim(mesh, part).map_err(mesh_error)?;
    let index_of: HashMap<usize, usize> = vertices
        .iter()
        .enumerate()
        .map(|(k, s)| (s.vertex, k))
        .collect();
    let zone_ends = rim
        .iter()
        .filter_map(|v| index_of.get(v))
        .map(|&node| ZoneEnd {
            node,
            limit: ZoneLimit::EndOfPart,
            body: body_index,
            part: part.to_string(),
        })
        .collect();
    let surface = surface_faces(mesh, part, &index_of).map_err(mesh_error)?;
    Ok(PairGeometry {
        nodes,
        inserted: 0,
        zone_ends,
        chain: false,
        surface: Some(surface),
    })
}
