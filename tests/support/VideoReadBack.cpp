// SPDX-License-Identifier: MIT
#include "VideoReadBack.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <catch2/catch.hpp>

namespace testsupport {

ReadBack readVideo(const std::string& path) {
  ReadBack out;
  AVFormatContext* format = nullptr;
  REQUIRE(avformat_open_input(&format, path.c_str(), nullptr, nullptr) == 0);
  REQUIRE(avformat_find_stream_info(format, nullptr) >= 0);
  const int s = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  REQUIRE(s >= 0);
  const AVCodecParameters* par = format->streams[s]->codecpar;
  out.codec = avcodec_get_name(par->codec_id);
  out.width = par->width;
  out.height = par->height;
  out.fps = av_q2d(format->streams[s]->avg_frame_rate);
  const AVCodec* decoder = avcodec_find_decoder(par->codec_id);
  REQUIRE(decoder);
  AVCodecContext* dec = avcodec_alloc_context3(decoder);
  REQUIRE(avcodec_parameters_to_context(dec, par) >= 0);
  REQUIRE(avcodec_open2(dec, decoder, nullptr) == 0);
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* sws = nullptr;
  auto drain = [&] {
    while (avcodec_receive_frame(dec, frame) == 0) {
      if (!sws)
        sws = sws_getContext(frame->width, frame->height, AVPixelFormat(frame->format), frame->width, frame->height,
                             AV_PIX_FMT_RGB24, SWS_BICUBIC, nullptr, nullptr, nullptr);
      // swscale writes whole SIMD blocks past a row's end: a padded, aligned buffer, then packed
      const int stride = (3 * frame->width + 63) / 64 * 64;
      std::vector<unsigned char> padded(size_t(stride) * frame->height + 64);
      uint8_t* planes[1] = {padded.data()};
      const int strides[1] = {stride};
      sws_scale(sws, frame->data, frame->linesize, 0, frame->height, planes, strides);
      std::vector<unsigned char> rgb(size_t(frame->width) * frame->height * 3);
      for (int y = 0; y < frame->height; ++y)
        std::copy_n(padded.data() + size_t(y) * stride, 3 * frame->width, rgb.data() + size_t(y) * 3 * frame->width);
      out.rgb.push_back(std::move(rgb));
    }
  };
  while (av_read_frame(format, packet) >= 0) {
    if (packet->stream_index == s) {
      ++out.frames;
      REQUIRE(avcodec_send_packet(dec, packet) == 0);
      drain();
    }
    av_packet_unref(packet);
  }
  avcodec_send_packet(dec, nullptr);
  drain();
  sws_freeContext(sws);
  av_frame_free(&frame);
  av_packet_free(&packet);
  avcodec_free_context(&dec);
  avformat_close_input(&format);
  return out;
}

}  // namespace testsupport
