//! A baked hierarchy as a file, for the host examples: `bake --out` writes one, `tessellate
//! --baked` reads it back, and `teapot` keeps one per model and bake settings as a cache, so
//! that a second start bakes nothing.
//!
//! The file is the hierarchy's records as they are in memory, little-endian, after a header
//! that says what they were baked from; a checksum closes it. It is checked whole when read:
//! the magic, the version, the model's fingerprint (the file belongs to the model it is read
//! with), the sizes and the checksum, then [`Hierarchy::new`](spline_tess::Hierarchy::new)
//! checks the records.
//!
//! ```text
//! "SPLTHIER"  version: u32  fingerprint: u64  settings: u64
//! nodes: u32  vertices: u32  patches: u32
//! nodes x 28 bytes, vertices x 36, patches x 68
//! checksum: u64 (FNV-1a of everything before it)
//! ```

use spline_tess::bake::{BakeSettings, Tolerance};
use spline_tess::tessellator::{
    HierarchyNode, HierarchyPatch, HierarchyVertex, SideLink, KEPT, NO_CONE,
};
use spline_tess::Side;

use super::model_file::{BakedHierarchy, ModelFile};

const MAGIC: &[u8; 8] = b"SPLTHIER";
const VERSION: u32 = 3;

/// FNV-1a, 64 bits.
pub fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    h
}

const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// A fingerprint of the model's patches: their headers, points and weights, bit for bit.
pub fn model_fingerprint(file: &ModelFile) -> u64 {
    let mut h = FNV_START;
    for header in &file.headers {
        h = fnv1a(&[header.degree_u, header.degree_v], h);
        h = fnv1a(&header.first_point.to_le_bytes(), h);
    }
    for p in &file.points {
        for c in p {
            h = fnv1a(&c.to_le_bytes(), h);
        }
    }
    for w in file.weights.iter().flatten() {
        h = fnv1a(&w.to_le_bytes(), h);
    }
    h
}

/// A fingerprint of the bake settings (and of this crate's version: a newer bake may differ).
pub fn settings_fingerprint(settings: &BakeSettings) -> u64 {
    let (kind, value) = match settings.tolerance {
        Tolerance::Absolute(t) => (0u8, t),
        Tolerance::Relative(t) => (1u8, t),
    };
    let mut h = fnv1a(env!("CARGO_PKG_VERSION").as_bytes(), FNV_START);
    h = fnv1a(&[kind, settings.max_depth], h);
    fnv1a(&value.to_le_bytes(), h)
}

fn side_code(s: Side) -> u8 {
    match s {
        Side::V0 => 0,
        Side::U1 => 1,
        Side::V1 => 2,
        Side::U0 => 3,
    }
}

fn side_of(code: u8) -> Option<Side> {
    Some(match code {
        0 => Side::V0,
        1 => Side::U1,
        2 => Side::V1,
        3 => Side::U0,
        _ => return None,
    })
}

/// The file's bytes for `baked`, baked from `file` with `settings`.
pub fn to_bytes(file: &ModelFile, settings: &BakeSettings, baked: &BakedHierarchy) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&model_fingerprint(file).to_le_bytes());
    out.extend_from_slice(&settings_fingerprint(settings).to_le_bytes());
    for n in [baked.nodes.len(), baked.vertices.len(), baked.patches.len()] {
        out.extend_from_slice(&(n as u32).to_le_bytes());
    }
    let f32s = |out: &mut Vec<u8>, v: &[f32]| {
        for x in v {
            out.extend_from_slice(&x.to_le_bytes());
        }
    };
    for n in &baked.nodes {
        out.extend_from_slice(&n.children.to_le_bytes());
        out.extend_from_slice(&n.vertex.to_le_bytes());
        for v in &n.vectors {
            out.extend(v.iter().map(|&c| c as u8));
        }
        f32s(&mut out, &[n.scale, n.remainder]);
    }
    for v in &baked.vertices {
        f32s(&mut out, &v.position);
        f32s(&mut out, &v.normal);
        out.extend_from_slice(&v.uv[0].to_le_bytes());
        out.extend_from_slice(&v.uv[1].to_le_bytes());
        out.extend_from_slice(&v.patch.to_le_bytes());
        out.extend_from_slice(&v.output.to_le_bytes());
    }
    for p in &baked.patches {
        for c in p.corners {
            out.extend_from_slice(&c.to_le_bytes());
        }
        for link in p.links {
            match link {
                Some(l) => {
                    out.extend_from_slice(&l.patch.to_le_bytes());
                    out.extend_from_slice(&[side_code(l.side), l.flip as u8]);
                }
                None => {
                    out.extend_from_slice(&u32::MAX.to_le_bytes());
                    out.extend_from_slice(&[0, 0]);
                }
            }
        }
        out.push(p.flip as u8);
        out.push(p.poles);
        f32s(&mut out, &p.cone);
        out.extend_from_slice(&p.cells);
        out.extend_from_slice(&p.first_root.to_le_bytes());
        out.extend_from_slice(&p.cell_vertices.to_le_bytes());
    }
    let sum = fnv1a(&out, FNV_START);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// A cursor over the file's bytes; every read past the end is an error.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let (head, rest) = self
            .bytes
            .split_first_chunk::<N>()
            .ok_or("the file ends early")?;
        self.bytes = rest;
        Ok(*head)
    }
    fn u32(&mut self) -> Result<u32, String> {
        self.take().map(u32::from_le_bytes)
    }
    fn u64(&mut self) -> Result<u64, String> {
        self.take().map(u64::from_le_bytes)
    }
    fn f32(&mut self) -> Result<f32, String> {
        self.take().map(f32::from_le_bytes)
    }
    fn f32x3(&mut self) -> Result<[f32; 3], String> {
        Ok([self.f32()?, self.f32()?, self.f32()?])
    }
}

/// The hierarchy `bytes` holds, baked from `file` (with `settings`, when given: the cache
/// takes only a bake of the same settings).
pub fn from_bytes(
    bytes: &[u8],
    file: &ModelFile,
    settings: Option<&BakeSettings>,
) -> Result<BakedHierarchy, String> {
    let body = bytes
        .len()
        .checked_sub(8)
        .map(|n| &bytes[..n])
        .ok_or("not a hierarchy file: too short")?;
    let mut r = Reader { bytes };
    if &r.take::<8>()? != MAGIC {
        return Err("not a hierarchy file".into());
    }
    let version = r.u32()?;
    if version != VERSION {
        return Err(format!("hierarchy file version {version}, not {VERSION}"));
    }
    if r.u64()? != model_fingerprint(file) {
        return Err("the hierarchy was baked from another model".into());
    }
    let baked_with = r.u64()?;
    if settings.is_some_and(|s| settings_fingerprint(s) != baked_with) {
        return Err("the hierarchy was baked with other settings".into());
    }
    let (nodes, vertices, patches) = (r.u32()? as usize, r.u32()? as usize, r.u32()? as usize);
    let expected = 8 + 4 + 8 + 8 + 12 + 28 * nodes + 36 * vertices + 68 * patches + 8;
    if bytes.len() != expected {
        return Err(format!(
            "hierarchy file of {} bytes, its header says {expected}",
            bytes.len()
        ));
    }
    let sum = u64::from_le_bytes(bytes[bytes.len() - 8..].try_into().expect("8 bytes"));
    if sum != fnv1a(body, FNV_START) {
        return Err("hierarchy file damaged: its checksum differs".into());
    }
    let mut out = BakedHierarchy {
        file: file.clone(),
        nodes: Vec::with_capacity(nodes),
        vertices: Vec::with_capacity(vertices),
        patches: Vec::with_capacity(patches),
    };
    for _ in 0..nodes {
        let (children, vertex) = (r.u32()?, r.u32()?);
        let mut vectors = [[0i8; 3]; KEPT];
        for v in &mut vectors {
            *v = r.take::<3>()?.map(|b| b as i8);
        }
        let (scale, remainder) = (r.f32()?, r.f32()?);
        out.nodes.push(HierarchyNode {
            children,
            vertex,
            vectors,
            scale,
            remainder,
        });
    }
    for _ in 0..vertices {
        let (position, normal) = (r.f32x3()?, r.f32x3()?);
        let uv = [u16::from_le_bytes(r.take()?), u16::from_le_bytes(r.take()?)];
        let (patch, output) = (r.u32()?, r.u32()?);
        out.vertices.push(HierarchyVertex {
            position,
            normal,
            uv,
            patch,
            output,
        });
    }
    for _ in 0..patches {
        let mut p = HierarchyPatch {
            cone: NO_CONE,
            ..HierarchyPatch::default()
        };
        for c in &mut p.corners {
            *c = r.u32()?;
        }
        for link in &mut p.links {
            let patch = r.u32()?;
            let [side, flip] = r.take::<2>()?;
            *link = match patch {
                u32::MAX => None,
                _ => Some(SideLink {
                    patch,
                    side: side_of(side).ok_or("hierarchy file: a side link is damaged")?,
                    flip: flip != 0,
                }),
            };
        }
        p.flip = r.take::<1>()?[0] != 0;
        p.poles = r.take::<1>()?[0];
        p.cone = [r.f32()?, r.f32()?, r.f32()?, r.f32()?];
        p.cells = r.take::<2>()?;
        p.first_root = r.u32()?;
        p.cell_vertices = r.u32()?;
        out.patches.push(p);
    }
    out.check()?;
    Ok(out)
}

/// The hierarchy of `file` baked with `settings`: read from `dir` when a file there holds it,
/// or baked (reporting to `progress`) and written there for the next time. The second value
/// is true when it came from `dir`.
pub fn cached(
    file: &ModelFile,
    settings: &BakeSettings,
    dir: &std::path::Path,
    progress: &mut dyn FnMut(spline_tess::bake::BakeProgress),
) -> Result<(BakedHierarchy, bool), String> {
    let name = format!(
        "{:016x}-{:016x}.hierarchy",
        model_fingerprint(file),
        settings_fingerprint(settings)
    );
    let path = dir.join(name);
    if let Ok(bytes) = std::fs::read(&path) {
        // A damaged or stale file is baked again (and overwritten).
        if let Ok(baked) = from_bytes(&bytes, file, Some(settings)) {
            return Ok((baked, true));
        }
    }
    let baked = BakedHierarchy::bake_with_progress(file, settings, progress)?;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    // Written whole under another name first, so that a run stopped halfway leaves no
    // half-written cache.
    let partial = path.with_extension("partial");
    std::fs::write(&partial, to_bytes(file, settings, &baked))
        .and_then(|()| std::fs::rename(&partial, &path))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok((baked, false))
}
