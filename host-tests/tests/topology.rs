//! Edge topology of every BPT model against the counts in examples/models/SOURCES.md.

use host_tests::{bpt_models, models_dir, name, KernelBpt};
use spline_tess::{BoundaryCurve, EdgeLink, Side, Topology, TopologyError};

/// (file, shared, open, collapsed) edge counts from SOURCES.md.
const EXPECTED: [(&str, usize, usize, usize); 6] = [
    ("teapot.bpt", 104, 16, 8),
    ("teapot_orig28.bpt", 88, 24, 0),
    ("teacup.bpt", 92, 12, 0),
    ("teaspoon.bpt", 56, 8, 0),
    ("gumbo.bpt", 494, 8, 10),
    ("teapot_westin.bpt", 104, 20, 4),
];

#[test]
fn every_model_has_the_documented_edge_counts() {
    assert_eq!(
        bpt_models().len(),
        EXPECTED.len(),
        "a model without expected counts"
    );
    for (file, shared, open, collapsed) in EXPECTED {
        let text = std::fs::read_to_string(models_dir().join(file)).unwrap();
        let kernel = KernelBpt::parse(&text);
        let set = kernel.set();
        let mut edges = vec![[EdgeLink::Collapsed; 4]; set.len()];
        let mut curves = vec![BoundaryCurve::default(); 4 * set.len()];
        let topo = Topology::build(&set, &mut edges, &mut curves).unwrap();
        let c = topo.edge_counts();
        assert_eq!(
            (c.shared, c.open, c.collapsed),
            (shared, open, collapsed),
            "{file}"
        );
        let uses: u32 = topo.curves().iter().map(|c| c.uses).sum();
        assert_eq!(uses as usize, shared + open, "{file}: curve uses");
        println!("{file}: {} distinct curves", topo.curves().len());

        // Every linked edge has the control points of its curve, in the stated direction.
        for (p, links) in topo.edges().iter().enumerate() {
            let patch = set.patch(p).unwrap();
            for side in Side::ALL {
                match links[side.index()] {
                    EdgeLink::Collapsed => assert!(patch.is_collapsed(side)),
                    EdgeLink::Curve { curve, reversed } => {
                        let owner = topo.curves()[curve as usize];
                        let op = set.patch(owner.patch as usize).unwrap();
                        let n = patch.edge_len(side);
                        assert_eq!(op.edge_len(owner.side), n);
                        for k in 0..n {
                            let kk = if reversed { n - 1 - k } else { k };
                            assert_eq!(
                                patch.edge_point(side, k),
                                op.edge_point(owner.side, kk),
                                "{file} patch {p} {side:?}"
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn small_buffers_report_what_is_needed() {
    for path in bpt_models() {
        let kernel = KernelBpt::parse(&std::fs::read_to_string(&path).unwrap());
        let set = kernel.set();
        let mut edges = vec![[EdgeLink::Collapsed; 4]; set.len()];
        let mut curves = vec![BoundaryCurve::default(); 4 * set.len()];
        let needed = Topology::build(&set, &mut edges, &mut curves)
            .unwrap()
            .curves()
            .len();
        let expected = TopologyError::BufferTooSmall {
            edges: set.len(),
            curves: needed,
        };
        let mut few = vec![BoundaryCurve::default(); needed - 1];
        let err = Topology::build(&set, &mut edges, &mut few).unwrap_err();
        assert_eq!(err, expected, "{}", name(&path));
        let mut short = vec![[EdgeLink::Collapsed; 4]; set.len() - 1];
        let err = Topology::build(&set, &mut short, &mut curves).unwrap_err();
        assert_eq!(err, expected, "{}", name(&path));
        let mut exact = vec![BoundaryCurve::default(); needed];
        assert!(Topology::build(&set, &mut edges, &mut exact).is_ok());
    }
}
