//! `bake diff` across topologies: bakes with other patch sizes compared with
//! `--mode means` and `--mode probes`; what cannot be compared (exit 2, naming the node, material
//! or probe and the files); unreadable inputs. (The time of a diff of two 10⁶-vertex outputs is
//! measured by `bench/diff_timing.py`.)

mod support;

use luxbake::settings::{ProbeGrid, Quality};
use support::bakes::*;
use support::scratch;

/// Another patch size changes every mesh: `--mode means` compares each node's and material's
/// area-weighted mean and the probes, whose places do not depend on the patches.
#[test]
fn other_patch_sizes_compare_by_means_and_probes() {
    let dir = scratch("diff-means");
    let scene = room(2400.0);
    let coarse = write(
        &dir,
        "coarse",
        "gltf",
        &scene,
        &settings(Quality::Draft, 0.5),
    );
    let fine = write(&dir, "fine", "gltf", &scene, &settings(Quality::Draft, 0.2));
    assert_eq!(diff(&coarse, &fine, &[]).code, Some(2));

    let (run, d) = diff_json(&coarse, &fine, &["--mode", "means", "--rtol", "1"]);
    assert_eq!(run.code, Some(0), "{}\n{}", run.stdout, run.stderr);
    assert_eq!(d["mode"], "means");
    let ill = quantity(&d, "illuminance");
    // 4 nodes and 3 materials, one mean each.
    assert_eq!(ill["overall"]["values"], 7);
    assert_eq!(ill["byNode"].as_array().unwrap().len(), 4);
    assert_eq!(ill["byMaterial"].as_array().unwrap().len(), 3);
    let floor_group = ill["byNode"]
        .as_array()
        .unwrap()
        .iter()
        .find(|g| g["name"] == "room/floor")
        .unwrap();
    let expect = (node_mean(&coarse, "floor") - node_mean(&fine, "floor")).abs();
    let got = number(&floor_group["abs"]["max"]);
    assert!(
        (got - expect).abs() <= 1e-9 * node_mean(&fine, "floor"),
        "{got} vs {expect}"
    );
    assert!(expect > 0.0);
    // Probe places are the same in both bakes: compared face by face.
    let probes = quantity(&d, "probeFaces");
    assert!(number(&probes["overall"]["values"]) >= 6.0 * 9.0);
    assert!(number(&probes["overall"]["rel"]["max"]) > 0.0);
    let plane = quantity(&d, "workingPlane");
    assert!(number(&plane["overall"]["values"]) >= 9.0);

    // A tight tolerance names the worst mean.
    let run = diff(&coarse, &fine, &["--mode", "means", "--rtol", "1e-6"]);
    assert_eq!(run.code, Some(1));
    let last = last_line(&run.stdout);
    assert!(last.starts_with("FAIL: "), "{last}");
    assert!(
        last.contains(" mean of node ")
            || last.contains(" mean of material ")
            || last.contains("probe "),
        "{last}"
    );
    assert!(
        run.stdout.contains("compared by area-weighted means"),
        "{}",
        run.stdout
    );

    // --mode probes: the probes alone.
    let (run, d) = diff_json(&coarse, &fine, &["--mode", "probes", "--rtol", "1"]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(quantity(&d, "illuminance")["overall"]["values"], 0);
    assert_eq!(
        quantity(&d, "probeFaces")["overall"],
        quantity(
            &diff_json(&coarse, &fine, &["--mode", "means", "--rtol", "1"]).1,
            "probeFaces"
        )["overall"]
    );
    // A bake with itself in either mode: all zero.
    for mode in ["means", "probes"] {
        let (run, d) = diff_json(&fine, &fine, &["--mode", mode]);
        assert_eq!(run.code, Some(0));
        assert_eq!(d["worst"].as_array().unwrap().len(), 0, "{mode}");
    }

    // Means need the same nodes and materials; probes the same probes.
    let renamed = copy(&fine, &dir, "renamed");
    let text = std::fs::read_to_string(&renamed).unwrap();
    std::fs::write(&renamed, text.replacen("\"white\"", "\"ivory\"", 1)).unwrap();
    let run = diff(&renamed, &coarse, &["--mode", "means"]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("material ivory (/materials/"),
        "{}",
        run.stderr
    );
    let run = diff(&renamed, &coarse, &["--mode", "probes", "--rtol", "1"]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let mut other = settings(Quality::Draft, 0.2);
    other.probe_grid = Some(ProbeGrid {
        spacing: 0.4,
        height: 0.5,
    });
    let moved = write(&dir, "moved", "gltf", &scene, &other);
    let run = diff(&moved, &fine, &["--mode", "probes"]);
    assert_eq!(run.code, Some(2));
    assert!(run.stderr.contains("probe probes/grid/"), "{}", run.stderr);
}

#[test]
fn different_topologies_cannot_be_compared() {
    let dir = scratch("diff-topology");
    let scene = room(2400.0);
    let b = write(&dir, "b", "gltf", &scene, &settings(Quality::Draft, 0.25));
    let a = write(&dir, "a", "gltf", &scene, &settings(Quality::Draft, 0.2));
    let run = diff(&a, &b, &[]);
    assert_eq!(run.code, Some(2), "{}", run.stdout);
    assert!(run.stdout.is_empty());
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    let floor = node_index(&b, "floor");
    let expect = format!(
        "error: {} and {} cannot be compared vertex by vertex: node room/floor (/nodes/{floor} in A, /nodes/{floor} in B) primitive 0: ",
        a.display(),
        b.display()
    );
    assert!(
        run.stderr.starts_with(&expect) && run.stderr.contains(" vertices vs "),
        "{}\nexpected {expect}",
        run.stderr
    );
    assert!(run.stderr.contains("--mode means"), "{}", run.stderr);
    // A renamed node is missing from the other file.
    let c = copy(&b, &dir, "renamed");
    let text = std::fs::read_to_string(&c).unwrap();
    std::fs::write(&c, text.replacen("\"wall_grey\"", "\"wall_gray\"", 1)).unwrap();
    let run = diff(&c, &b, &[]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains(&format!(
            "node room/wall_gray (/nodes/{} in A): missing in B",
            node_index(&b, "wall_grey")
        )),
        "{}",
        run.stderr
    );
    // A moved vertex.
    let m = copy(&b, &dir, "moved");
    let at = offset(&m, "floor", 0, "POSITION", 2);
    let mut bin = std::fs::read(bin_of(&m)).unwrap();
    let y = read_f32(&bin, at + 4) + 1e-3;
    bin[at + 4..at + 8].copy_from_slice(&y.to_le_bytes());
    std::fs::write(bin_of(&m), bin).unwrap();
    let run = diff(&m, &b, &[]);
    assert_eq!(run.code, Some(2));
    assert!(
        run.stderr.contains("in B) primitive 0 vertex 2: at "),
        "{}",
        run.stderr
    );
    // Not a luxbake output, a missing file, an OBJ.
    let input = dir.join("input.gltf");
    std::fs::write(&input, support::cli::Mini::new().document(None).to_string()).unwrap();
    for other in [input, dir.join("nothing.gltf"), dir.join("x.obj")] {
        let run = diff(&other, &b, &[]);
        assert_eq!(run.code, Some(2), "{other:?}");
        assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
        assert!(run.stderr.starts_with("error: "), "{}", run.stderr);
    }
}
