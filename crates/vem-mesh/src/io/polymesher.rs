//! Polygonal meshes in the layout of PolyMesher (Talischi et al. 2012: `Node`, `Element`) and
//! mVEM (`node`, `elem`), exported from MATLAB as text.
//!
//! The file has sections, each a keyword line with a count, then that many lines:
//!
//! ```text
//! NODES 6            # then one node per line: x y
//! 0 0
//! ...
//! ELEMENTS 2         # then one polygon per line: its node numbers from 1, in order
//! 1 2 5 4
//! 2 3 6 5
//! PART bottom 2      # optional, any number: a name and its boundary edges, node pairs from 1
//! 1 2
//! 2 3
//! ```
//!
//! `#` starts a comment; blank lines are skipped. Node numbers count from 1 as in MATLAB.
//! Polygons given clockwise are turned counter-clockwise. MATLAB writes it with
//!
//! ```text
//! fid = fopen('mesh.txt', 'w');
//! fprintf(fid, 'NODES %d\n', size(node, 1)); fprintf(fid, '%.17g %.17g\n', node');
//! fprintf(fid, 'ELEMENTS %d\n', numel(elem));
//! for k = 1:numel(elem), fprintf(fid, '%d ', elem{k}); fprintf(fid, '\n'); end
//! fprintf(fid, 'PART dirichlet %d\n', size(bdEdgeD, 1)); fprintf(fid, '%d %d\n', bdEdgeD');
//! fclose(fid);
//! ```
//!
//! (`elem` a matrix, as for triangles: `num2cell(elem, 2)` first; PolyMesher's `Node`,
//! `Element` in place of `node`, `elem`; mVEM's `setboundary` gives `bdStruct.bdEdgeD` and
//! `bdEdgeN`.)

use std::path::Path;

use crate::{geometry, Mesh, MeshError, PartSpec, Point};

/// Reads a polygonal mesh from a text file in the PolyMesher/mVEM layout (see the module
/// documentation). Errors are [`MeshError::Read`] naming the file and the line.
///
/// ```
/// let text = "NODES 4\n0 0\n1 0\n1 1\n0 1\nELEMENTS 1\n1 2 3 4\nPART bottom 1\n1 2\n";
/// let mesh = vem_mesh::io::read_polymesher_bytes(text.as_bytes(), "square.txt")?;
/// assert_eq!(mesh.area(0), 1.0);
/// assert_eq!(mesh.part_names(), ["bottom"]);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn read_polymesher(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| MeshError::Read {
        path: path.to_path_buf(),
        reason: format!("cannot read the file: {e}"),
    })?;
    read_polymesher_bytes(&bytes, path)
}

/// Reads a mesh in the PolyMesher/mVEM text layout from bytes; `name` is the file name used in
/// error messages.
pub fn read_polymesher_bytes(bytes: &[u8], name: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    parse(bytes).map_err(|reason| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason,
    })
}

/// The lines of the file that hold something: (line number from 1, words).
fn content_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(k, line)| {
        let line = line.split('#').next().unwrap_or("");
        let words: Vec<&str> = line.split_whitespace().collect();
        (!words.is_empty()).then_some((k + 1, words))
    })
}

/// A `PART` section: its line, its name, and its edges with their lines.
type Part = (usize, String, Vec<(usize, [usize; 2])>);

fn parse(bytes: &[u8]) -> Result<Mesh, String> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| format!("byte {}: the file is not text", e.valid_up_to()))?;
    let mut lines = content_lines(text).peekable();
    let mut nodes: Option<Vec<Point>> = None;
    let mut elements: Option<Vec<(usize, Vec<usize>)>> = None;
    let mut parts: Vec<Part> = Vec::new();
    let count = |line: usize, word: Option<&&str>, what: &str| -> Result<usize, String> {
        let word = word.ok_or_else(|| format!("line {line}: {what} is missing"))?;
        word.parse()
            .map_err(|_| format!("line {line}: {what} is '{word}', not a count"))
    };
    // Every entry takes at least two bytes: a count beyond that is a damaged file.
    let bounded = |line: usize, n: usize| -> Result<usize, String> {
        if n > bytes.len() / 2 + 1 {
            Err(format!(
                "line {line}: the count {n} is more than the file can hold"
            ))
        } else {
            Ok(n)
        }
    };
    let node_number = |line: usize, word: &str, n: usize| -> Result<usize, String> {
        match word.parse::<usize>() {
            Ok(k) if (1..=n).contains(&k) => Ok(k - 1),
            _ => Err(format!(
                "line {line}: node number '{word}' is not one of the {n} nodes (numbered from 1)"
            )),
        }
    };
    while let Some((line, words)) = lines.next() {
        match words[0].to_ascii_uppercase().as_str() {
            "NODES" => {
                if nodes.is_some() {
                    return Err(format!("line {line}: a second NODES section"));
                }
                let n = bounded(line, count(line, words.get(1), "the number of nodes")?)?;
                let mut list = Vec::with_capacity(n);
                for k in 0..n {
                    let (at, words) = lines
                        .next()
                        .ok_or_else(|| format!("the file ends after {k} of {n} nodes"))?;
                    let coordinate = |i: usize| -> Result<f64, String> {
                        let word = words.get(i).ok_or_else(|| {
                            format!(
                                "line {at}: node {} has no {} coordinate",
                                k + 1,
                                ["x", "y"][i]
                            )
                        })?;
                        match word.parse::<f64>() {
                            Ok(v) if v.is_finite() => Ok(v),
                            _ => Err(format!(
                                "line {at}: coordinate {} of node {} is '{word}', not a finite \
                                 number",
                                ["x", "y"][i],
                                k + 1
                            )),
                        }
                    };
                    if words.len() > 3 {
                        return Err(format!(
                            "line {at}: node {} has {} numbers; expected x y",
                            k + 1,
                            words.len()
                        ));
                    }
                    list.push(Point::new(coordinate(0)?, coordinate(1)?));
                }
                nodes = Some(list);
            }
            "ELEMENTS" => {
                if elements.is_some() {
                    return Err(format!("line {line}: a second ELEMENTS section"));
                }
                let n = bounded(line, count(line, words.get(1), "the number of elements")?)?;
                let n_nodes = nodes
                    .as_ref()
                    .ok_or_else(|| format!("line {line}: ELEMENTS before NODES"))?
                    .len();
                let mut list = Vec::with_capacity(n);
                for k in 0..n {
                    let (at, words) = lines
                        .next()
                        .ok_or_else(|| format!("the file ends after {k} of {n} elements"))?;
                    let polygon = words
                        .iter()
                        .map(|w| node_number(at, w, n_nodes))
                        .collect::<Result<Vec<_>, _>>()?;
                    list.push((at, polygon));
                }
                elements = Some(list);
            }
            "PART" => {
                let name = words
                    .get(1)
                    .ok_or_else(|| format!("line {line}: PART needs a name and a count"))?
                    .to_string();
                let n = bounded(line, count(line, words.get(2), "the number of edges")?)?;
                let n_nodes = nodes
                    .as_ref()
                    .ok_or_else(|| format!("line {line}: PART before NODES"))?
                    .len();
                let mut edges = Vec::with_capacity(n);
                for k in 0..n {
                    let (at, words) = lines.next().ok_or_else(|| {
                        format!("the file ends after {k} of the {n} edges of part '{name}'")
                    })?;
                    if words.len() != 2 {
                        return Err(format!(
                            "line {at}: an edge of part '{name}' is two node numbers, found {}",
                            words.len()
                        ));
                    }
                    edges.push((
                        at,
                        [
                            node_number(at, words[0], n_nodes)?,
                            node_number(at, words[1], n_nodes)?,
                        ],
                    ));
                }
                parts.push((line, name, edges));
            }
            other => {
                return Err(format!(
                    "line {line}: expected NODES, ELEMENTS or PART, found '{other}'"
                ))
            }
        }
    }
    let all_nodes = nodes.ok_or("the file has no NODES section")?;
    let mut elements = elements.ok_or("the file has no ELEMENTS section")?;
    // Nodes that no element uses are dropped (the others keep their order).
    let mut vertex_of = vec![usize::MAX; all_nodes.len()];
    for (_, polygon) in &elements {
        for &v in polygon {
            vertex_of[v] = 0;
        }
    }
    let mut nodes = Vec::new();
    for (k, point) in all_nodes.iter().enumerate() {
        if vertex_of[k] == 0 {
            vertex_of[k] = nodes.len();
            nodes.push(*point);
        }
    }
    for (_, polygon) in &mut elements {
        for v in polygon.iter_mut() {
            *v = vertex_of[*v];
        }
    }
    for (_, name, edges) in &parts {
        if let Some((line, _)) = edges
            .iter()
            .find(|(_, [a, b])| vertex_of[*a] == usize::MAX || vertex_of[*b] == usize::MAX)
        {
            return Err(format!(
                "line {line}: an edge of part '{name}' has a node that no element uses"
            ));
        }
    }
    let parts: Vec<_> = parts
        .into_iter()
        .map(|(line, name, edges)| {
            let edges = edges
                .into_iter()
                .map(|(at, [a, b])| (at, [vertex_of[a], vertex_of[b]]))
                .collect::<Vec<_>>();
            (line, name, edges)
        })
        .collect();
    let mut offsets = vec![0];
    let mut indices = Vec::new();
    for (line, polygon) in &elements {
        if polygon.len() < 3 {
            return Err(format!(
                "line {line}: an element of {} nodes; a polygon has at least 3",
                polygon.len()
            ));
        }
        let start = indices.len();
        indices.extend_from_slice(polygon);
        let points: Vec<Point> = polygon.iter().map(|&v| nodes[v]).collect();
        if geometry::signed_area(&points) < 0.0 {
            indices[start..].reverse();
        }
        offsets.push(indices.len());
    }
    let specs = parts
        .into_iter()
        .map(|(_, name, edges)| PartSpec::new(name, edges.into_iter().map(|(_, e)| e).collect()))
        .collect();
    let n_polygons = elements.len();
    Mesh::from_compact(nodes, offsets, indices, specs).map_err(|e| {
        format!(
            "the mesh it describes is invalid: {e} (polygons are its {n_polygons} elements, \
             vertices the nodes they use, both numbered from 0 in file order)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        read_polymesher_bytes(text.as_bytes(), "m.txt")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn two_squares_one_clockwise() {
        let text = "# two squares\nNODES 6\n0 0\n1 0\n2 0\n0 1\n1 1\n2 1\n\nELEMENTS 2\n\
                    1 2 5 4\n2 5 6 3  # clockwise\nPART bottom 2\n1 2\n3 2\n";
        let mesh = read_polymesher_bytes(text.as_bytes(), "m.txt").unwrap();
        assert_eq!(mesh.n_polygons(), 2);
        assert!((0..2).all(|p| mesh.area(p) == 1.0));
        assert_eq!(mesh.part("bottom").unwrap().edges.len(), 2);
    }

    #[test]
    fn defects_name_the_line() {
        assert_eq!(
            error("NODES 2\n0 0\n1 x\n"),
            "m.txt: line 3: coordinate y of node 2 is 'x', not a finite number"
        );
        assert_eq!(
            error("NODES 3\n0 0\n1 0\n0 1\nELEMENTS 1\n1 2 4\n"),
            "m.txt: line 6: node number '4' is not one of the 3 nodes (numbered from 1)"
        );
        assert_eq!(
            error("NODES 3\n0 0\n1 0\n0 1\nELEMENTS 1\n1 2 0\n"),
            "m.txt: line 6: node number '0' is not one of the 3 nodes (numbered from 1)"
        );
        assert_eq!(
            error("NODES 99999999999\n"),
            "m.txt: line 1: the count 99999999999 is more than the file can hold"
        );
        assert_eq!(
            error("NODES 4\n0 0\n1 0\n0 1\n1 1\nELEMENTS 1\n1 2 3\nPART top 1\n3 4\n"),
            "m.txt: line 9: an edge of part 'top' has a node that no element uses"
        );
        let message =
            error("NODES 4\n0 0\n1 0\n0 1\n1 1\nELEMENTS 2\n1 2 4\n1 4 3\nPART diagonal 1\n1 4\n");
        assert!(
            message.contains("boundary part 'diagonal' names edge (0, 3), which is interior"),
            "{message}"
        );
    }
}
