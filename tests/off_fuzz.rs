//! Property tests: whatever the bytes, the OFF reader returns Ok or Err,
//! never panics, and what it returns is usable (finite positions, indices
//! in range).

use proptest::prelude::*;
use refract::mesh::off::parse_off;

const SEEDS: &[&str] = &[
    "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n",
    "# c\nOFF6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 0 1 2 3 4 5 0.5 0.5 0.5\n",
];

fn check(bytes: &[u8]) {
    if let Ok(m) = parse_off(bytes, "fuzz.off") {
        assert!(m.positions.iter().all(|p| p.is_finite()));
        assert!(m.triangles.iter().flatten().all(|&i| (i as usize) < m.positions.len()));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        check(&bytes);
    }

    #[test]
    fn random_token_soup_never_panics(toks in proptest::collection::vec(prop_oneof![
        Just("OFF".to_string()), Just("COFF".to_string()), Just("\n".to_string()), Just("#".to_string()),
        Just("-1".to_string()), Just("nan".to_string()), Just("1e40".to_string()), Just("4294967296".to_string()),
        (0u32..12).prop_map(|v| v.to_string()), (-2.0f32..2.0).prop_map(|v| v.to_string()),
    ], 0..80)) {
        check(toks.join(" ").as_bytes());
    }

    #[test]
    fn mutated_valid_files_never_panic(seed in 0usize..SEEDS.len(), edits in proptest::collection::vec((any::<u16>(), 0u8..4, any::<u8>()), 1..8)) {
        let mut b = SEEDS[seed].as_bytes().to_vec();
        let alphabet = b"0123456789 \n\t#-.eEOFCNnax";
        for (pos, op, v) in edits {
            let at = if b.is_empty() { 0 } else { pos as usize % b.len() };
            let c = alphabet[v as usize % alphabet.len()];
            match op {
                0 if !b.is_empty() => { b.remove(at); }
                1 => b.insert(at, c),
                2 if !b.is_empty() => b[at] = c,
                _ => b.truncate(at),
            }
        }
        check(&b);
    }
}
