//! Reading accessors: the bytes of a buffer view checked against its buffer, strided
//! elements of any component type (normalised or not), sparse substitutions, with every
//! offset and count checked so a malformed file is an error, never a panic.

use super::*;

/// Size in bytes of one component.
fn component_size(ty: gltf::accessor::DataType) -> usize {
    use gltf::accessor::DataType;
    match ty {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// One component at the start of `bytes` (little-endian), normalised to 0..1 or -1..1 when
/// `normalized`. `bytes` holds at least [`component_size`] bytes.
fn component(bytes: &[u8], ty: gltf::accessor::DataType, normalized: bool) -> f64 {
    use gltf::accessor::DataType;
    let array = |n: usize| -> [u8; 4] {
        let mut out = [0; 4];
        out[..n].copy_from_slice(&bytes[..n]);
        out
    };
    let (value, scale) = match ty {
        DataType::I8 => (f64::from(bytes[0] as i8), 127.0),
        DataType::U8 => (f64::from(bytes[0]), 255.0),
        DataType::I16 => {
            let [a, b, ..] = array(2);
            (f64::from(i16::from_le_bytes([a, b])), 32767.0)
        }
        DataType::U16 => {
            let [a, b, ..] = array(2);
            (f64::from(u16::from_le_bytes([a, b])), 65535.0)
        }
        DataType::U32 => (f64::from(u32::from_le_bytes(array(4))), 4_294_967_295.0),
        DataType::F32 => return f64::from(f32::from_le_bytes(array(4))),
    };
    if normalized {
        (value / scale).max(-1.0)
    } else {
        value
    }
}

impl Loader<'_> {
    /// The bytes of a buffer view, checked against its buffer.
    pub(super) fn view_bytes(&self, view: &gltf::buffer::View<'_>) -> Result<&[u8], GltfError> {
        let buffer = &self.buffers[view.buffer().index()];
        let end = view.offset().checked_add(view.length());
        match end {
            Some(end) if end <= buffer.len() => Ok(&buffer[view.offset()..end]),
            _ => Err(self.invalid(format!(
                "buffer view {} spans bytes {}..{} of buffer {}, which holds {}",
                view.index(),
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index(),
                buffer.len()
            ))),
        }
    }

    /// `count` elements of `element` bytes at `offset` in a view, `stride` apart; checks
    /// that they lie inside the view.
    fn strided(
        &self,
        view: &gltf::buffer::View<'_>,
        offset: usize,
        count: usize,
        element: usize,
        stride: usize,
        what: &str,
    ) -> Result<&[u8], GltfError> {
        let data = self.view_bytes(view)?;
        if count == 0 {
            return Ok(&[]);
        }
        if stride < element {
            return Err(self.invalid(format!(
                "{what}: byteStride {stride} is smaller than its {element}-byte elements"
            )));
        }
        let end = stride
            .checked_mul(count - 1)
            .and_then(|n| n.checked_add(offset))
            .and_then(|n| n.checked_add(element));
        match end {
            Some(end) if end <= data.len() => Ok(&data[offset..end]),
            _ => Err(self.invalid(format!(
                "{what}: {count} elements from byte {offset} run past the end of buffer view {} \
                 ({} bytes)",
                view.index(),
                data.len()
            ))),
        }
    }

    /// Every element of an accessor with `components` components, as f64 (normalised where
    /// the accessor says so), sparse substitutions applied.
    pub(super) fn read(
        &self,
        accessor: &gltf::Accessor<'_>,
        components: usize,
        what: &str,
    ) -> Result<Vec<f64>, GltfError> {
        let what = format!("{what} ({})", describe("accessor", accessor.index(), None));
        if accessor.dimensions().multiplicity() != components {
            return Err(self.invalid(format!(
                "{what} has {:?} elements, {components} component(s) expected",
                accessor.dimensions()
            )));
        }
        let ty = accessor.data_type();
        let size = component_size(ty);
        let element = size * components;
        let count = accessor.count();
        if count.saturating_mul(components) > MAX_ACCESSOR_VALUES {
            return Err(self.invalid(format!(
                "{what} has {count} elements, more than the {MAX_ACCESSOR_VALUES} values \
                 aa-lab reads from one accessor"
            )));
        }
        let normalized = accessor.normalized();
        let decode = |bytes: &[u8], out: &mut Vec<f64>| {
            for c in 0..components {
                out.push(component(&bytes[c * size..], ty, normalized));
            }
        };
        let mut values = Vec::with_capacity(count * components);
        match accessor.view() {
            Some(view) => {
                let stride = view.stride().unwrap_or(element);
                let bytes =
                    self.strided(&view, accessor.offset(), count, element, stride, &what)?;
                for i in 0..count {
                    decode(&bytes[i * stride..], &mut values);
                }
            }
            None => values.resize(count * components, 0.0),
        }
        if let Some(sparse) = accessor.sparse() {
            let indices = sparse.indices();
            let index_type = match indices.index_type() {
                gltf::accessor::sparse::IndexType::U8 => gltf::accessor::DataType::U8,
                gltf::accessor::sparse::IndexType::U16 => gltf::accessor::DataType::U16,
                gltf::accessor::sparse::IndexType::U32 => gltf::accessor::DataType::U32,
            };
            let index_size = component_size(index_type);
            let sparse_what = format!("{what}, sparse");
            let index_bytes = self.strided(
                &indices.view(),
                indices.offset(),
                sparse.count(),
                index_size,
                index_size,
                &format!("{sparse_what} indices"),
            )?;
            let value_bytes = self.strided(
                &sparse.values().view(),
                sparse.values().offset(),
                sparse.count(),
                element,
                element,
                &format!("{sparse_what} values"),
            )?;
            let mut substitute = Vec::with_capacity(components);
            for i in 0..sparse.count() {
                let target = component(&index_bytes[i * index_size..], index_type, false);
                if target >= count as f64 {
                    return Err(self.invalid(format!(
                        "{sparse_what} index {target} is out of range: the accessor has {count} \
                         elements"
                    )));
                }
                substitute.clear();
                decode(&value_bytes[i * element..], &mut substitute);
                let at = target as usize * components;
                values[at..at + components].copy_from_slice(&substitute);
            }
        }
        Ok(values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_normalise() {
        use gltf::accessor::DataType;
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x01, 0x00], DataType::U16, false), 1.0);
        assert_eq!(component(&1.5f32.to_le_bytes(), DataType::F32, true), 1.5);
    }
}
