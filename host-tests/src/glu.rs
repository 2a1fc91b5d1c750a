//! libGLU's NURBS tessellator as a peer: the binary built from `host-tests/glu/glu_peer.c` (as
//! `scripts/figures.sh` builds it) run on a model's patches for one camera, its triangles and
//! its time read back.

use std::io::Write;
use std::process::{Command, Stdio};

use crate::reference::{RefPatch, V3};

fn widen(p: [f32; 3]) -> V3 {
    p.map(|x| x as f64)
}

/// What the GLU peer wrote: each triangle's patch, corner parameters and corner points, and
/// its best time in milliseconds.
pub struct GluRun {
    /// Each triangle's patch, corner parameters and corner points.
    pub triangles: Vec<(usize, [[f64; 2]; 3], [V3; 3])>,
    /// Its best time of fifteen, in milliseconds, the tessellation alone.
    pub ms: f64,
}

/// The column-major OpenGL matrices of a look-at camera (up +z) and a perspective projection
/// of `fov` degrees vertically, as `gluLookAt` and `gluPerspective` build them.
pub fn gl_matrices(
    eye: V3,
    target: V3,
    fov: f64,
    aspect: f64,
    near: f64,
    far: f64,
) -> [[f64; 16]; 2] {
    use crate::reference::{cross, dot};
    let unit = |a: V3| {
        let l = dot(a, a).sqrt();
        [a[0] / l, a[1] / l, a[2] / l]
    };
    let f = unit([target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]]);
    let s = unit(cross(f, [0.0, 0.0, 1.0]));
    let u = cross(s, f);
    let t = [-dot(s, eye), -dot(u, eye), dot(f, eye)];
    let modelview = [
        s[0], u[0], -f[0], 0.0, //
        s[1], u[1], -f[1], 0.0, //
        s[2], u[2], -f[2], 0.0, //
        t[0], t[1], t[2], 1.0,
    ];
    let g = 1.0 / (fov.to_radians() * 0.5).tan();
    let projection = [
        g / aspect,
        0.0,
        0.0,
        0.0, //
        0.0,
        g,
        0.0,
        0.0, //
        0.0,
        0.0,
        (far + near) / (near - far),
        -1.0, //
        0.0,
        0.0,
        2.0 * far * near / (near - far),
        0.0,
    ];
    [modelview, projection]
}

/// Runs the GLU peer `binary` on the patches for one camera (a look-at camera, up +z,
/// 40 degrees vertically, the far plane 1e5 times the near one) at `tol` pixels.
pub fn run_glu(
    binary: &str,
    refs: &[RefPatch],
    eye: [f32; 3],
    target: [f32; 3],
    viewport: [u32; 2],
    near: f32,
    tol: f64,
) -> GluRun {
    let aspect = viewport[0] as f64 / viewport[1] as f64;
    let [modelview, projection] = gl_matrices(
        widen(eye),
        widen(target),
        40.0,
        aspect,
        near as f64,
        near as f64 * 1e5,
    );
    let mut input = format!(
        "viewport {} {}\ntolerance {tol}\nmodelview",
        viewport[0], viewport[1]
    );
    for x in modelview {
        input += &format!(" {x:e}");
    }
    input += "\nprojection";
    for x in projection {
        input += &format!(" {x:e}");
    }
    input += &format!("\npatches {}\n", refs.len());
    for r in refs {
        input += &format!("{} {}\n", r.du, r.dv);
        for (p, w) in r.pts.iter().zip(&r.w) {
            input += &format!("{:e} {:e} {:e} {w:e}\n", p[0], p[1], p[2]);
        }
    }
    let mut child = Command::new(binary)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("the GLU peer runs");
    child
        .stdin
        .take()
        .expect("a pipe")
        .write_all(input.as_bytes())
        .expect("the GLU peer reads its input");
    let out = child.wait_with_output().expect("the GLU peer finishes");
    assert!(out.status.success(), "the GLU peer failed");
    let text = String::from_utf8(out.stdout).expect("UTF-8");
    let mut run = GluRun {
        triangles: Vec::new(),
        ms: f64::NAN,
    };
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("t") => {
                let n: Vec<f64> = words.map(|w| w.parse().expect("a number")).collect();
                let corner = |c: usize| &n[1 + 5 * c..6 + 5 * c];
                run.triangles.push((
                    n[0] as usize,
                    core::array::from_fn(|c| [corner(c)[0], corner(c)[1]]),
                    core::array::from_fn(|c| [corner(c)[2], corner(c)[3], corner(c)[4]]),
                ));
            }
            Some("ms") => {
                run.ms = words
                    .next()
                    .and_then(|w| w.parse().ok())
                    .unwrap_or(f64::NAN)
            }
            _ => {}
        }
    }
    run
}
