// Each invocation stops at its first syntax error, so each gets its own.
shapegen::generator! {
    struct A;
    shape: [cube];
    start: N;
    node N { |s| {} }
}
shapegen::generator! {
    struct B;
    start: N;
    node N { slot { next: N = 0.5 } |s| {} }
}
shapegen::generator! {
    struct C;
    start: N;
    node N emit { |s| {} }
}
shapegen::generator! {
    struct D;
    start: N;
    limits: { max_lenght: 10 };
    node N { |s| {} }
}
shapegen::generator! {
    struct E;
    start: N;
    node N { params { x: float = uniform(0, 1) } |s| {} }
}
shapegen::generator! {
    struct F;
    start: N;
    node N { params { x: uniform(0, 1) } |s| {} }
}
shapegen::generator! {
    struct H;
    start: Nd;
    node N { params { x: f32 = unifrom(0, 1) } slots { next: Nod = 0.5 } |s| {} }
}
fn main() {}
