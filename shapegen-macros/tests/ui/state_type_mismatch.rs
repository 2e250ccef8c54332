shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A emits {
        slots { next: A = 0.5 }
        |s| {
            emit!(cube, s);
            child!(next, 2.0);
        }
    }
}
fn main() {}
