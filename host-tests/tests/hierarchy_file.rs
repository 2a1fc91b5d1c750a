//! The examples' hierarchy file (`examples/common/hierarchy_file.rs`, the main job's cache):
//! what it writes reads back as the same records, every field of them, and a damaged or
//! foreign file is refused (the main job then bakes again). A field left out of the file once
//! made every second start bake again, silently.

#[allow(dead_code)]
#[path = "../../examples/common/hierarchy_file.rs"]
mod hierarchy_file;

use hierarchy_file::{from_bytes, to_bytes};
use host_tests::model_file;
use host_tests::models_dir;
use model_file::{BakedHierarchy, ModelFile};
use spline_tess::bake::{BakeSettings, Tolerance};

fn read(name: &str) -> ModelFile {
    ModelFile::read(models_dir().join(name).to_str().unwrap()).unwrap()
}

#[test]
fn a_hierarchy_file_reads_back_as_the_same_records() {
    for name in ["teapot.bpt", "nurbs/rational_torus.json"] {
        let file = read(name);
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(1e-2),
            ..BakeSettings::default()
        };
        let baked = BakedHierarchy::bake(&file, &settings).unwrap();
        assert!(baked.patches.iter().any(|p| p.cells != [0, 0]), "{name}");
        let bytes = to_bytes(&file, &settings, &baked);
        let back = from_bytes(&bytes, &file, Some(&settings)).unwrap();
        assert_eq!(back.nodes, baked.nodes, "{name}");
        assert_eq!(back.vertices, baked.vertices, "{name}");
        assert_eq!(back.patches, baked.patches, "{name}");
        // Other settings, another model, a changed byte: refused.
        let other = BakeSettings {
            tolerance: Tolerance::Relative(2e-2),
            ..settings
        };
        assert!(from_bytes(&bytes, &file, Some(&other)).is_err());
        assert!(from_bytes(&bytes, &read("teaspoon.bpt"), Some(&settings)).is_err());
        let mut damaged = bytes.clone();
        damaged[bytes.len() / 2] ^= 1;
        assert!(from_bytes(&damaged, &file, Some(&settings)).is_err());
    }
}
