//! How much geometry a scene instances, counted from its accessors before any is read: a
//! small file can draw one mesh from thousands of nodes, and each node's copy is read,
//! transformed and uploaded whole.

use std::path::Path;

use gltf::mesh::Mode;

use super::accessor::check_range;
use crate::error::{Error, Result};

/// Most triangles a scene reads over all its mesh nodes: 4 Mi. A scene at the limit reads
/// and uploads about 0.5 GB (positions, normals, tangents, uvs and indices, and the GPU's
/// copy); one mesh drawn by 20,000 nodes once took 7.5 GB and 65 s before it was refused.
pub const MAX_TRIANGLES: usize = 1 << 22;

/// Most vertices a scene reads over all its mesh nodes: the same 4 Mi (a vertex costs about
/// what a triangle does).
pub const MAX_VERTICES: usize = 1 << 22;

/// Refuses a scene whose mesh nodes, in all, instance more than [`MAX_TRIANGLES`] triangles
/// or [`MAX_VERTICES`] vertices, counting each node's mesh once per node. An accessor whose
/// data lies outside its buffer counts nothing here: reading it is refused with that reason.
pub(super) fn check_instanced(path: &Path, nodes: &[gltf::Node], buffers: &[gltf::buffer::Data]) -> Result<()> {
    let (mut triangles, mut vertices, mut instances) = (0usize, 0usize, 0usize);
    for mesh in nodes.iter().filter_map(gltf::Node::mesh) {
        instances += 1;
        for primitive in mesh.primitives() {
            let (t, v) = size(&primitive, buffers);
            triangles = triangles.saturating_add(t);
            vertices = vertices.saturating_add(v);
        }
    }
    let (nodes, verb) = if instances == 1 { ("node", "instances") } else { ("nodes", "instance") };
    let refuse = |what: &str, count: usize, limit: usize| {
        Err(Error::format(
            path,
            format!("the scene's {instances} mesh {nodes} {verb} {count} {what}; at most {limit} are read (share fewer nodes, or simplify the mesh)"),
        ))
    };
    if triangles > MAX_TRIANGLES {
        return refuse("triangles", triangles, MAX_TRIANGLES);
    }
    if vertices > MAX_VERTICES {
        return refuse("vertices", vertices, MAX_VERTICES);
    }
    Ok(())
}

/// The triangles and vertices of one triangle primitive, by its accessors' counts (0 for
/// points and lines, which are skipped).
fn size(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data]) -> (usize, usize) {
    let Some(positions) = primitive.get(&gltf::Semantic::Positions) else { return (0, 0) };
    let vertices = count(&positions, buffers);
    let order = primitive.indices().map_or(vertices, |a| count(&a, buffers));
    match primitive.mode() {
        Mode::Triangles => (order / 3, vertices),
        Mode::TriangleStrip | Mode::TriangleFan => (order.saturating_sub(2), vertices),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => (0, 0),
    }
}

/// The elements of an accessor, or 0 when its data does not lie inside its buffer view.
fn count(accessor: &gltf::Accessor, buffers: &[gltf::buffer::Data]) -> usize {
    match accessor.view() {
        Some(view) => check_range(&view, buffers, accessor.offset(), accessor.count(), accessor.size()).map_or(0, |()| accessor.count()),
        None => accessor.count(),
    }
}
