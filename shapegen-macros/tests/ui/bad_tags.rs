shapegen::generator! {
    struct G;
    start: S;
    node S {
        slots { a: A = 1.0, b: B = 1.0, c: C = 1.0 }
        tags { trunk, trunk }
        |s| { child!(a, s); child!(b, s); child!(c, s); }
    }
    node A, B {
        tags { branch, each[left, right, up] }
        |s| {}
    }
    node C {
        tags { each[one] , zweigé }
        |s| {}
    }
}
fn main() {}
