// Semantic tags: shared by a family, per member with `each[..]`, several
// per node; they reach the graph and leave its fingerprint alone.
use shapegen::prelude::*;

shapegen::generator! {
    pub struct Tagged;
    shapes: [cube];
    start: S;

    node S {
        slots { a: A = 1.0, b: B = 1.0 }
        |scope| { child!(a, scope); child!(b, scope); }
    }

    node A, B emits {
        tags { branch, each[left, right], r#type }
        |scope| { emit!(cube, scope.instance()); }
    }
}

shapegen::generator! {
    pub struct Untagged;
    shapes: [cube];
    start: S;

    node S {
        slots { a: A = 1.0, b: B = 1.0 }
        |scope| { child!(a, scope); child!(b, scope); }
    }

    node A, B emits {
        |scope| { emit!(cube, scope.instance()); }
    }
}

pub fn main() {
    let g = Tagged.graph();
    let tags = |name: &str| -> Vec<String> {
        let id = g.node_id(name).unwrap();
        g.node(id).tags.iter().map(|t| t.to_string()).collect()
    };
    assert!(tags("S").is_empty());
    assert_eq!(tags("A"), ["branch", "left", "type"]);
    assert_eq!(tags("B"), ["branch", "right", "type"]);
    assert_eq!(g.fingerprint(), Untagged.graph().fingerprint());
}
