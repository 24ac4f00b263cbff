//! Accessors checked against their buffers before they are read, so that reading one
//! cannot fail half-way.

use gltf::accessor::{DataType, Dimensions, Item};

/// Checks an accessor's shape and type, and that all its bytes (and those of its sparse
/// substitution, if any) lie inside its buffer view and the view inside the buffer's data,
/// so that reading it cannot fail half-way (gltf's reader would otherwise stop short or, in
/// debug builds, assert).
pub(super) fn check_accessor(
    accessor: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
    name: &str,
    dimensions: Dimensions,
    types: &[DataType],
) -> std::result::Result<(), String> {
    let index = accessor.index();
    if accessor.count() == 0 {
        return Err(format!("{name} accessor {index} is empty"));
    }
    if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
        return Err(format!(
            "{name} accessor {index} is {:?} {:?}; supported: {:?} of {:?}",
            accessor.dimensions(),
            accessor.data_type(),
            dimensions,
            types
        ));
    }
    let element = accessor.size();
    let out_of_range = || format!("{name} accessor {index} lies outside its buffer (truncated or corrupt file?)");
    if let Some(view) = accessor.view() {
        check_range(&view, buffers, accessor.offset(), accessor.count(), element).ok_or_else(out_of_range)?;
    }
    if let Some(sparse) = accessor.sparse() {
        let count = sparse.count();
        if count == 0 || count > accessor.count() {
            return Err(format!("{name} accessor {index} has {count} sparse values for {} elements", accessor.count()));
        }
        let (indices, values) = (sparse.indices(), sparse.values());
        check_range(&indices.view(), buffers, indices.offset(), count, indices.index_type().size())
            .ok_or_else(out_of_range)?;
        check_range(&values.view(), buffers, values.offset(), count, element).ok_or_else(out_of_range)?;
    }
    Ok(())
}

/// `Some(())` when `count` elements of `element` bytes from `offset` (at the view's stride) lie
/// inside the view, and the view inside its buffer's data.
pub(super) fn check_range(
    view: &gltf::buffer::View,
    buffers: &[gltf::buffer::Data],
    offset: usize,
    count: usize,
    element: usize,
) -> Option<()> {
    let stride = view.stride().unwrap_or(element);
    if stride < element || count == 0 {
        return None;
    }
    let end = stride.checked_mul(count - 1)?.checked_add(element)?.checked_add(offset)?;
    let view_end = view.offset().checked_add(view.length())?;
    let data = buffers.get(view.buffer().index())?;
    (end <= view.length() && view_end <= data.0.len()).then_some(())
}

/// The elements of an accessor of `N` components as floats, whatever its component type
/// (KHR_mesh_quantization stores positions, normals, tangents and texture coordinates as
/// 8- or 16-bit integers): a normalized integer is mapped to [0, 1] or [−1, 1] as glTF
/// prescribes ($\max(c / (2^{b-1} - 1), -1)$ when signed, $c / (2^b - 1)$ when not), any
/// other read as its value. `None` when its data lies outside its buffer.
pub(super) fn read_floats<const N: usize>(accessor: &gltf::Accessor, buffers: &[gltf::buffer::Data]) -> Option<Vec<[f32; N]>>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
    [u32; N]: Item,
{
    let normalized = accessor.normalized();
    let signed = move |c: f32, max: f32| if normalized { (c / max).max(-1.0) } else { c };
    let unsigned = move |c: f32, max: f32| if normalized { c / max } else { c };
    match accessor.data_type() {
        DataType::F32 => read_as::<f32, N>(accessor, buffers, |c| c),
        DataType::I8 => read_as::<i8, N>(accessor, buffers, |c| signed(c as f32, 127.0)),
        DataType::U8 => read_as::<u8, N>(accessor, buffers, |c| unsigned(c as f32, 255.0)),
        DataType::I16 => read_as::<i16, N>(accessor, buffers, |c| signed(c as f32, 32767.0)),
        DataType::U16 => read_as::<u16, N>(accessor, buffers, |c| unsigned(c as f32, 65535.0)),
        DataType::U32 => read_as::<u32, N>(accessor, buffers, |c| c as f32),
    }
}

/// The elements of an accessor of `N` components of type `T`, each mapped by `value`.
fn read_as<T: Copy, const N: usize>(accessor: &gltf::Accessor, buffers: &[gltf::buffer::Data], value: impl Fn(T) -> f32) -> Option<Vec<[f32; N]>>
where
    [T; N]: Item,
{
    let data = |b: gltf::Buffer| buffers.get(b.index()).map(|d| &d.0[..]);
    let iter = gltf::accessor::Iter::<[T; N]>::new(accessor.clone(), data)?;
    Some(iter.map(|e| e.map(&value)).collect())
}
