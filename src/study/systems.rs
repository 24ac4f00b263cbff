//! The systems of `brdfpaint bench --tables`, written for a reference implementation to time
//! (`tools/reference/cholesky.py`, DESIGN.md's numpy/scipy Cholesky peer): each case's
//! design matrix $\mathbf A$, its regularization rows $\mathbf R$ (so that
//! $\mathbf G = \mathbf A^\top \mathbf A + \mathbf R^\top \mathbf R + \epsilon \mathbf I$,
//! eq. 3.4 with smoothing), the samples' directions and values, each factor's table and the
//! log mapping's offset, as `.npy` files numpy reads without a parser of ours.

use std::path::Path;

use crate::commit::{Claim, Legacy, StagedDir};
use crate::error::{Error, Result};
use crate::factor::system::{self, Design};
use crate::factor::{Pattern, Settings};

/// One case's system, as the reference needs it.
pub struct System<'a> {
    pub name: &'a str,
    pub pattern: &'a Pattern,
    pub settings: &'a Settings,
    pub values: &'a [[f64; 3]],
    /// The offset mapping's a (log(f + a)), the same for every channel.
    pub offset: f64,
}

/// Writes every system into `dir` (whole or not at all): `NN.a_indptr.npy`, `NN.a_indices.npy`,
/// `NN.a_data.npy`, the same three for `r`, `NN.values.npy`, `NN.queries.npy` (l, v, uv per
/// sample, from which the reference builds its own A), and `cases.json` naming them with
/// each case's factors.
pub fn write(dir: &Path, systems: &[System<'_>]) -> Result<()> {
    let staged = StagedDir::new(dir, Claim::new(&[], Legacy::Paths(Default::default())))?;
    let mut index = Vec::new();
    for (k, s) in systems.iter().enumerate() {
        let stem = format!("{k:02}");
        let design = Design::new(s.pattern, s.settings)?;
        let reg = system::regularization(s.settings, &design);
        let rows = design.rows();
        let queries: Vec<f64> = s.pattern.queries.iter().flat_map(|q| [q.l.x, q.l.y, q.l.z, q.v.x, q.v.y, q.v.z, q.uv.x, q.uv.y]).collect();
        let files: [(&str, Vec<u8>); 8] = [
            ("a_indptr", npy_u32(&design.row_ptr)),
            ("a_indices", npy_u32(&design.row_col)),
            ("a_data", npy_f64(&design.row_val, &[design.row_val.len()])),
            ("r_indptr", npy_u32(&reg_ptr(&reg))),
            ("r_indices", npy_u32(&reg.iter().flatten().map(|&(i, _)| i as u32).collect::<Vec<_>>())),
            ("r_data", npy_f64(&reg.iter().flatten().map(|&(_, x)| x).collect::<Vec<_>>(), &[reg.iter().map(Vec::len).sum()])),
            ("values", npy_f64(&s.values.iter().flatten().copied().collect::<Vec<_>>(), &[s.values.len(), 3])),
            ("queries", npy_f64(&queries, &[s.pattern.len(), 8])),
        ];
        for (part, bytes) in files {
            staged.write(&format!("{stem}.{part}.npy"), |p| std::fs::write(p, bytes).map_err(|e| Error::io(p, e)))?;
        }
        index.push(serde_json::json!({
            "case": s.name,
            "stem": stem,
            "samples": rows,
            "unknowns": design.n,
            "regularization_rows": reg.len(),
            // The diagonal floor of `system::normal_matrix`.
            "floor": 1e-12 * rows as f64 / design.n as f64,
            "offset": s.offset,
            "factors": s.settings.factors,
        }));
    }
    let json = serde_json::to_string_pretty(&index).map_err(|e| Error::input(e.to_string()))?;
    staged.write("cases.json", |p| std::fs::write(p, json).map_err(|e| Error::io(p, e)))?;
    staged.commit()
}

/// Row pointers of the regularization rows.
fn reg_ptr(reg: &crate::factor::table::Rows) -> Vec<u32> {
    let mut ptr = vec![0u32];
    for r in reg {
        ptr.push(ptr[ptr.len() - 1] + r.len() as u32);
    }
    ptr
}

/// A version 1.0 `.npy` file: magic, a header dict padded to 64 bytes, raw little-endian data.
fn npy(descr: &str, shape: &[usize], data: &[u8]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape = if dims.len() == 1 { format!("({},)", dims[0]) } else { format!("({})", dims.join(", ")) };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend((header.len() as u16).to_le_bytes());
    out.extend(header.as_bytes());
    out.extend(data);
    out
}

fn npy_u32(v: &[u32]) -> Vec<u8> {
    npy("<u4", &[v.len()], &v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<_>>())
}

fn npy_f64(v: &[f64], shape: &[usize]) -> Vec<u8> {
    npy("<f8", shape, &v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<_>>())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::SphereView;

    /// The data of a `.npy` file as little-endian 8-byte or 4-byte numbers (by its descr).
    fn read_npy(path: &Path) -> Vec<f64> {
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
        let data = &bytes[10 + len..];
        if header.contains("'<u4'") {
            data.chunks(4).map(|c| u32::from_le_bytes(c.try_into().unwrap()) as f64).collect()
        } else {
            assert!(header.contains("'<f8'"), "{header}");
            data.chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect()
        }
    }

    #[test]
    fn written_systems_rebuild_the_normal_matrix() {
        let pattern = SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), 20).pattern();
        let settings = Settings::four_factor(1, 8, 6);
        let values = vec![[0.5, 0.25, 0.125]; pattern.len()];
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("systems");
        write(&out, &[System { name: "small", pattern: &pattern, settings: &settings, values: &values, offset: 0.05 }]).unwrap();
        let cases: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("cases.json")).unwrap()).unwrap();
        let n = cases[0]["unknowns"].as_u64().unwrap() as usize;
        let part = |p: &str| read_npy(&out.join(format!("00.{p}.npy")));
        let mut g = vec![0.0; n * n];
        for m in ["a", "r"] {
            let (ptr, idx, val) = (part(&format!("{m}_indptr")), part(&format!("{m}_indices")), part(&format!("{m}_data")));
            for r in 0..ptr.len() - 1 {
                for k in ptr[r] as usize..ptr[r + 1] as usize {
                    for l in ptr[r] as usize..ptr[r + 1] as usize {
                        g[idx[k] as usize * n + idx[l] as usize] += val[k] * val[l];
                    }
                }
            }
        }
        let floor = cases[0]["floor"].as_f64().unwrap();
        let design = Design::new(&pattern, &settings).unwrap();
        let truth = system::normal_matrix(&design, &settings, None).to_dense();
        let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            for j in 0..n {
                let mine = g[i * n + j] + if i == j { floor } else { 0.0 };
                assert!((mine - truth[(i, j)]).abs() <= 1e-12 * scale, "G[{i}, {j}]: {mine} against {}", truth[(i, j)]);
            }
        }
        assert_eq!(part("values").len(), 3 * pattern.len());
        assert_eq!(part("values")[2], 0.125);
    }

    #[test]
    fn npy_header_is_padded_to_64_bytes_and_holds_the_shape() {
        let bytes = npy_f64(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], &[2, 3]);
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
        assert!(header.contains("'shape': (2, 3)"), "{header}");
        assert_eq!(bytes.len(), 10 + len + 48);
        assert_eq!(f64::from_le_bytes(bytes[10 + len + 40..].try_into().unwrap()), 6.0);
    }
}
