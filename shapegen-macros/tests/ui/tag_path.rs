shapegen::generator! {
    struct G;
    start: S;
    node S {
        tags { mass::lvl0 }
        |s| {}
    }
}
fn main() {}
