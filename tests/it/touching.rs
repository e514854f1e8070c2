//! Issue 51 item 3: "touching" means one thing in every output (`sim::scene::touch`): a
//! made solid contact, or surfaces within 1e-6 of the smaller radius.

use crate::common::{printed, trubal_json};

fn u(v: &serde_json::Value) -> u64 {
    v.as_u64().unwrap_or_else(|| panic!("not a count: {v}"))
}

/// The thesis's BCC example (§5.3): its nearest neighbours are 3.8e-11 m apart (R given to
/// seven digits) and carry no force, yet they are its 8000 contacts, before and after
/// `cycle 10`, in PRint Info, PRint Contacts, CHist and CLUsters, human and JSON alike.
#[test]
fn the_bcc_example_has_its_8000_contacts_in_every_output() {
    let bcc = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scripts/bcc_example.tru"
    ))
    .unwrap();
    let items = "print info contacts chist clusters\n";
    let run = trubal_json(&format!("{bcc}{items}cycle 10\n{items}"), &[]);
    assert!(run.ok, "{}", run.stderr);
    let info = printed(&run, "info");
    let contacts = printed(&run, "contacts");
    let chist = printed(&run, "chist");
    let clusters = printed(&run, "clusters");
    // (The script's own `print info`, then the two of this test.)
    assert_eq!(info.len(), 3);
    for k in 0..2 {
        let i = &info[k + 1];
        assert_eq!(u(&i["contacts"]), 8000, "{i}");
        assert_eq!(u(&i["touching"]), 8000, "{i}");
        assert_eq!(u(&i["active_contacts"]), 0, "{i}");
        let list = contacts[k]["contacts"].as_array().unwrap();
        assert_eq!(list.len(), 8000);
        assert_eq!(contacts[k]["evaluated"], k == 1);
        for c in list {
            assert_eq!(c["touching"], true, "{c}");
            assert_eq!(c["active"], false, "{c}");
            // The gap, shown as a negative overlap.
            let o = c["overlap"].as_f64().unwrap();
            assert!(o < 0.0 && o > -1e-10, "{c}");
        }
        assert_eq!(chist[k]["coordination"].as_f64().unwrap(), 8.0);
        assert_eq!(u(&clusters[k]["largest"]), 2000);
    }
    // The human outputs say the same.
    let human = crate::cli::run(&format!("{bcc}cycle 10\nprint info\np c\n"), &["-"]);
    assert!(human.0, "{}", human.2);
    assert!(
        human
            .1
            .contains("contacts 8000 particle-particle, 0 particle-wall"),
        "{}",
        human.1
    );
    let rows = human.1.lines().filter(|l| l.contains("e-11")).count();
    assert_eq!(rows, 8000);
}

/// A gap of 1e-4 R is not touching anywhere, a made contact is, and a sphere resting within
/// round-off of a wall touches it.
#[test]
fn a_real_gap_does_not_touch_and_a_wall_counts_alike() {
    let head = "start 1e-3 1e-3 1e-3 10 10 2\nrad 1e-4 1\ndensity 2650 1\nymd 7e10 1\npra 0.3 1\n";
    // Pair 1-2 with a gap of 1e-8 m (1e-4 R); 3 overlapping 1 by 1e-9 m; 4 within 1e-11 m
    // of the floor z = 0.
    let s = format!(
        "{head}set genoverlap 1e-3\ndwall p 0 0 1 0 m 1\ncreate 3e-4 3e-4 3e-4 0 0 0 0 0 0 1 1\n\
         create 3e-4 3e-4 {:.12e} 0 0 0 0 0 0 1 1\ncreate {:.12e} 3e-4 3e-4 0 0 0 0 0 0 1 1\n\
         create 7e-4 7e-4 {:.12e} 0 0 0 0 0 0 1 1\nprint info contacts\ncycle 1\nprint info contacts\n",
        3e-4 + 2e-4 + 1e-8,
        3e-4 + 2e-4 - 1e-9,
        1e-4 + 1e-11
    );
    let run = trubal_json(&s, &[]);
    assert!(run.ok, "{}", run.stderr);
    let info = printed(&run, "info");
    let contacts = printed(&run, "contacts");
    for k in 0..2 {
        assert_eq!(u(&info[k]["contacts"]), 1, "{}", info[k]);
        assert_eq!(u(&info[k]["wall_contacts"]), 1, "{}", info[k]);
        let list = contacts[k]["contacts"].as_array().unwrap();
        assert_eq!(list.len(), 2, "{list:?}");
        assert!(list.iter().all(|c| c["touching"] == true));
        assert!(
            list.iter()
                .any(|c| c["a"] == 1 && c["b"] == 3 && c["overlap"].as_f64().unwrap() > 0.0)
        );
        assert!(list.iter().any(|c| c["a"] == 4 && c["wall"] == 1));
    }
    // After the step: the overlapping pair's law acts, the pair 1-2 is no contact.
    assert_eq!(u(&info[1]["active_contacts"]), 1);
    assert_eq!(contacts[1]["evaluated"], true);
}
