shapegen::generator! {
    struct G;
    start: S;
    node S {
        slots { a: A = 1.0, b: B = 1.0, c: C = 1.0 }
        |s| { child!(a, s); child!(b, s); child!(c, s); }
    }
    node A, B {
        params { len: f32 = each[uniform(0, 1), uniform(1, 2), uniform(2, 3)] }
        slots { next: A = each[0.5] }
        |s| { child!(next, s); }
    }
    node C {
        consts { k: f32 = each[1.0, 2.0] }
        |s| {}
    }
}
fn main() {}
